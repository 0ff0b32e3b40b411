//! `uniffi-bindgen`: UniFFI's command-line generator at exactly the UniFFI
//! version the FFI crate is built with, as UniFFI recommends for a
//! workspace. Bindings are generated from the built library:
//!
//! ```sh
//! uniffi-bindgen generate --library target/release/liblikeness_ffi.so \
//!     --language python --out-dir build/python
//! ```

fn main() {
    uniffi::uniffi_bindgen_main()
}
