//! The FFI's `CaptureSession` driven by any sequence of calls (see
//! `likeness_fuzz::capture_driver`): frames with time going back, NaN and
//! wrong sizes, skips, retakes of any step, previews, finish and the
//! handle it returns.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(init: { likeness_fuzz::capture_driver::face(); }, |data: &[u8]| {
    likeness_fuzz::capture_driver::run(data);
});
