//! The Khronos glTF-Validator, run under Node from `tests/js` (pinned in
//! its `package-lock.json`; `tests/run` installs it). A test that needs it
//! skips with a one-line notice when Node or the validator is missing,
//! unless `LIKENESS_REQUIRE_TOOLS=1` (as `tests/run` sets), where a
//! missing tool fails the test.

use serde_json::Value;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Whether tests must fail rather than skip when a tool they need is
/// missing: `LIKENESS_REQUIRE_TOOLS=1`.
pub fn tools_required() -> bool {
    std::env::var("LIKENESS_REQUIRE_TOOLS").as_deref() == Ok("1")
}

/// The validator's JSON report on each of `files`, in order; `None`, after
/// a notice naming `test`, when Node or the validator is not installed and
/// tools are not [required](tools_required). Panics when the validator
/// itself fails to run.
pub fn validate(test: &str, files: &[PathBuf]) -> Option<Vec<Value>> {
    let js = Path::new(env!("CARGO_MANIFEST_DIR")).join("js");
    let installed = js.join("node_modules/gltf-validator").is_dir();
    let node = Command::new("node").arg("--version").output().is_ok();
    if !(installed && node) {
        assert!(
            !tools_required(),
            "{test}: LIKENESS_REQUIRE_TOOLS=1 but the glTF-Validator (or Node) is missing: \
             run `tests/run` or `npm ci` in tests/js"
        );
        // Straight to stderr, past the test harness's capture, so the skip
        // shows in a passing run.
        let _ = writeln!(
            std::io::stderr(),
            "{test}: skipped, the glTF-Validator is not installed (npm ci in tests/js)"
        );
        return None;
    }
    let out = Command::new("node")
        .arg(js.join("validate.mjs"))
        .args(files)
        .output()
        .expect("node runs");
    assert!(
        out.status.success(),
        "the validator failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    Some(serde_json::from_slice(&out.stdout).expect("the validator's JSON"))
}
