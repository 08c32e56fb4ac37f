//! From the scene model back to scene-file descriptions: what `lucent
//! convert` writes.

// Used by the scene exporter (`lucent convert`); until it lands only the
// round-trip tests call it.
#[allow(dead_code)]
mod materials;

#[allow(unused_imports)]
pub(crate) use materials::*;
