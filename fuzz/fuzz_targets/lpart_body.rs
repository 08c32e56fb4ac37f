#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    lucent::tools::readers::Reader::LpartBody.feed(data);
});
