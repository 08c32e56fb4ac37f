//! Finding and loading Intel Open Image Denoise (OIDN) 2.x at run time.
//!
//! lucent does not link OIDN: it builds and runs without it, and opens the
//! shared library only when asked to denoise, from the first of:
//!
//! 1. `$LUCENT_OIDN`: the library file itself, or a folder holding it;
//! 2. the system's library search path (`LD_LIBRARY_PATH`, `ldconfig`'s
//!    folders; `DYLD_LIBRARY_PATH` on macOS, `PATH` on Windows);
//! 3. the `pyoidn` wheel from PyPI (`pip install pyoidn`), which ships the
//!    library with its weights and TBB in `pyoidn/oidn/lib`: looked for in
//!    the active virtual environment (`$VIRTUAL_ENV`), then where
//!    `python3` finds the `pyoidn` package.
//!
//! Only the C functions below are called, declared from OIDN's public
//! header `OpenImageDenoise/oidn.h` (version 2 API; the wheel has no
//! headers).

use std::ffi::{c_char, c_int, c_void, CStr};
use std::path::{Path, PathBuf};

/// The shared library's file name on this platform (OIDN 2's soname).
#[cfg(target_os = "linux")]
pub const LIBRARY_NAME: &str = "libOpenImageDenoise.so.2";
/// The shared library's file name on this platform (OIDN 2's soname).
#[cfg(target_os = "macos")]
pub const LIBRARY_NAME: &str = "libOpenImageDenoise.2.dylib";
/// The shared library's file name on this platform (OIDN 2's soname).
#[cfg(windows)]
pub const LIBRARY_NAME: &str = "OpenImageDenoise.dll";
/// The shared library's file name on this platform (OIDN 2's soname).
#[cfg(not(any(target_os = "linux", target_os = "macos", windows)))]
pub const LIBRARY_NAME: &str = "libOpenImageDenoise.so.2";

/// The environment variable that names the library or its folder.
pub const LIBRARY_VARIABLE: &str = "LUCENT_OIDN";

/// Why OIDN cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// No library was found anywhere.
    #[error(
        "Intel Open Image Denoise 2 was not found: install it with `pip install pyoidn` (the PyPI wheel ships the library), \
         or set {LIBRARY_VARIABLE} to the path of {LIBRARY_NAME} or its folder, or put that folder on the library search path ({searched})"
    )]
    NotFound {
        /// Where lucent looked.
        searched: String,
    },
    /// A library was found but cannot be opened or is not OIDN 2.
    #[error("cannot use Intel Open Image Denoise from {path}: {message}")]
    Unusable {
        /// The library.
        path: String,
        /// What went wrong.
        message: String,
    },
}

// OIDN's opaque handles.
pub(super) type Device = *mut c_void;
pub(super) type Filter = *mut c_void;

/// The functions of OIDN's C API that lucent calls.
pub(super) struct Api {
    pub new_device: unsafe extern "C" fn(c_int) -> Device,
    pub commit_device: unsafe extern "C" fn(Device),
    pub release_device: unsafe extern "C" fn(Device),
    pub set_device_int: unsafe extern "C" fn(Device, *const c_char, c_int),
    pub get_device_error: unsafe extern "C" fn(Device, *mut *const c_char) -> c_int,
    pub new_filter: unsafe extern "C" fn(Device, *const c_char) -> Filter,
    pub set_shared_filter_image:
        unsafe extern "C" fn(Filter, *const c_char, *mut c_void, c_int, usize, usize, usize, usize, usize),
    pub set_filter_bool: unsafe extern "C" fn(Filter, *const c_char, bool),
    pub set_filter_int: unsafe extern "C" fn(Filter, *const c_char, c_int),
    pub commit_filter: unsafe extern "C" fn(Filter),
    pub execute_filter: unsafe extern "C" fn(Filter),
    pub release_filter: unsafe extern "C" fn(Filter),
}

/// An opened OIDN library.
pub struct Library {
    pub(super) api: Api,
    path: String,
    // Kept open for as long as the function pointers in `api` are used.
    _library: libloading::Library,
}

impl std::fmt::Debug for Library {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Library").field("path", &self.path).finish()
    }
}

impl Library {
    /// Find and open OIDN (see the module documentation for where).
    pub fn find() -> Result<Library, LoadError> {
        let mut searched = Vec::new();
        if let Some(v) = std::env::var_os(LIBRARY_VARIABLE).filter(|v| !v.is_empty()) {
            let given = PathBuf::from(v);
            let path = if given.is_dir() { given.join(LIBRARY_NAME) } else { given };
            // The user named it: any problem is theirs to see, not a reason
            // to look elsewhere.
            if !path.exists() {
                return Err(LoadError::Unusable {
                    path: path.display().to_string(),
                    message: format!("{LIBRARY_VARIABLE} names it, but there is no such file"),
                });
            }
            return Library::open(&path);
        }
        searched.push(format!("{LIBRARY_VARIABLE} is not set"));
        // The system's search path: the bare name.
        if let Ok(library) = Library::open(Path::new(LIBRARY_NAME)) {
            return Ok(library);
        }
        searched.push("not on the library search path".into());
        for dir in pyoidn_folders() {
            let path = dir.join(LIBRARY_NAME);
            if path.is_file() {
                return Library::open(&path);
            }
            searched.push(format!("not in {}", dir.display()));
        }
        if searched.len() == 2 {
            searched.push("no pyoidn package found".into());
        }
        Err(LoadError::NotFound { searched: searched.join("; ") })
    }

    /// Open the library at `path` (a bare file name is looked up on the
    /// system's search path) and check that it is OIDN 2.
    pub fn open(path: &Path) -> Result<Library, LoadError> {
        let shown = path.display().to_string();
        let unusable = |message: String| LoadError::Unusable { path: shown.clone(), message };
        // SAFETY: loading a library runs its initialisers. OIDN's are those
        // of a well-behaved C++ library (static objects, TBB); the path is
        // the user's choice or OIDN's own soname.
        let library = unsafe { libloading::Library::new(path.as_os_str()) }.map_err(|e| unusable(e.to_string()))?;
        macro_rules! symbol {
            ($name:literal) => {
                // SAFETY: the types are those of `oidn.h` (version 2) for
                // this symbol, and the pointer is used only while `library`
                // is held (both live in the returned `Library`).
                *unsafe { library.get(concat!($name, "\0").as_bytes()) }
                    .map_err(|e| unusable(format!("it lacks {}: {e} (is it Open Image Denoise 2?)", $name)))?
            };
        }
        let api = Api {
            new_device: symbol!("oidnNewDevice"),
            commit_device: symbol!("oidnCommitDevice"),
            release_device: symbol!("oidnReleaseDevice"),
            set_device_int: symbol!("oidnSetDeviceInt"),
            get_device_error: symbol!("oidnGetDeviceError"),
            new_filter: symbol!("oidnNewFilter"),
            set_shared_filter_image: symbol!("oidnSetSharedFilterImage"),
            set_filter_bool: symbol!("oidnSetFilterBool"),
            set_filter_int: symbol!("oidnSetFilterInt"),
            commit_filter: symbol!("oidnCommitFilter"),
            execute_filter: symbol!("oidnExecuteFilter"),
            release_filter: symbol!("oidnReleaseFilter"),
        };
        Ok(Library { api, path: shown, _library: library })
    }

    /// Where the library was opened from.
    pub fn path(&self) -> &str {
        &self.path
    }

    /// The message of the device's last error, if any, clearing it.
    pub(super) fn device_error(&self, device: Device) -> Option<String> {
        let mut message: *const c_char = std::ptr::null();
        // SAFETY: `device` is a live device of this library; OIDN writes a
        // pointer to a NUL-terminated string it owns (or null) that stays
        // valid until the next call on the device, and it is copied now.
        let code = unsafe { (self.api.get_device_error)(device, &mut message) };
        (code != 0).then(|| {
            let text = if message.is_null() {
                String::new()
            } else {
                // SAFETY: see above: non-null and NUL-terminated.
                unsafe { CStr::from_ptr(message) }.to_string_lossy().into_owned()
            };
            format!("{} (OIDN error {code})", if text.is_empty() { "unknown error" } else { &text })
        })
    }
}

/// Folders where a `pyoidn` wheel keeps the library: the active virtual
/// environment's, then the one `python3` finds (without importing it).
fn pyoidn_folders() -> Vec<PathBuf> {
    let mut dirs = Vec::new();
    let mut package_roots = Vec::new();
    if let Some(venv) = std::env::var_os("VIRTUAL_ENV") {
        let lib = PathBuf::from(venv).join("lib");
        if let Ok(entries) = std::fs::read_dir(&lib) {
            for e in entries.flatten() {
                package_roots.push(e.path().join("site-packages").join("pyoidn"));
            }
        }
    }
    let script = "import importlib.util as u\ns = u.find_spec('pyoidn')\nprint(s.submodule_search_locations[0] if s and s.submodule_search_locations else '')";
    for python in ["python3", "python"] {
        if let Ok(out) = std::process::Command::new(python).args(["-c", script]).output() {
            let found = String::from_utf8_lossy(&out.stdout).trim().to_owned();
            if out.status.success() && !found.is_empty() {
                package_roots.push(PathBuf::from(found));
            }
            break;
        }
    }
    for root in package_roots {
        let dir = root.join("oidn").join(if cfg!(windows) { "bin" } else { "lib" });
        if !dirs.contains(&dir) {
            dirs.push(dir);
        }
    }
    dirs
}
