# Shared by smoke.sh and campaign.sh (sourced): the pinned cargo-fuzz, the
# targets with their dictionary and longest input, the limits, the build
# and the seeds. See README.md for why each value.

# meshoptimizer, vendored by the `meshopt` crate (the GLB reader's
# EXT_meshopt_compression decoder), defines a file-local global `edges` in
# two of its C++ files; AddressSanitizer's one-definition-rule check aborts
# every instrumented binary on it at start-up. It is not a memory error:
# that one check is turned off, every other stays on.
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_odr_violation=0"

# The cargo-fuzz these scripts were written against (installed if missing).
CARGO_FUZZ_VERSION=0.13.1

# libFuzzer's memory limits: a single allocation of MALLOC_LIMIT_MB or more,
# or a resident size past RSS_LIMIT_MB, is a crash (an out-of-memory). The
# inputs are at most a few tens of kilobytes, so anything near these is a
# length that was trusted; the resident size includes AddressSanitizer's
# shadow and quarantine and, for capture_ffi, a committed session loaded
# once.
RSS_LIMIT_MB=2048
MALLOC_LIMIT_MB=512
# Seconds one input may take before it counts as a hang.
TIMEOUT_S=30

# target:dictionary:max_len (bytes; a little above the largest seed).
TARGET_SPECS=(
  session_bytes:session:8192
  session_payload:session:8192
  session_deflate:session:8192
  obj:obj:4096
  weights_csv:csv:8192
  frames_csv:csv:16384
  live_link_csv:live_link:16384
  folder_import:folder:40000
  glb:glb:32768
  capture_ffi:session:1024
)

FUZZ_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$FUZZ_DIR/../.." && pwd)"
# Where cargo puts the targets: tests/fuzz/target, or CARGO_TARGET_DIR
# when that is set; in the folder of the host's triple (cargo fuzz builds
# with --target).
TARGET_DIR="$(cargo metadata --format-version 1 --no-deps \
  --manifest-path "$FUZZ_DIR/Cargo.toml" |
  python3 -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')"
BIN="$TARGET_DIR/$(rustc -vV | sed -n 's/^host: //p')/release"
# cargo-fuzz passes -Zsanitizer and friends, nightly flags: this makes the
# stable toolchain accept them.
export RUSTC_BOOTSTRAP=1

# Installs the pinned cargo-fuzz if it is missing or another version.
ensure_cargo_fuzz() {
  if ! cargo fuzz --version 2>/dev/null | grep -q "$CARGO_FUZZ_VERSION"; then
    cargo install cargo-fuzz --version "$CARGO_FUZZ_VERSION" --locked
  fi
}

# Builds every target (release, AddressSanitizer: cargo-fuzz's defaults)
# and make_seeds, in one cargo run.
build_targets() {
  (cd "$ROOT" && cargo fuzz build --fuzz-dir tests/fuzz)
}

# Writes the generated seeds into $1 (with --large as $2, also the
# real-sized ones under $1/large).
make_seeds() {
  "$BIN/make_seeds" "$@"
}

# The field NAME of a libFuzzer log's final stats (-print_final_stats=1).
final_stat() {
  grep -o "stat::$2: *[0-9]*" "$1" | tail -1 | grep -o '[0-9]*$' || echo 0
}

# Removes the scratch folders (/dev/shm/likeness-fuzz-PID) of targets no
# longer running.
clean_scratch() {
  local dir pid
  for dir in /dev/shm/likeness-fuzz-* /tmp/likeness-fuzz-*; do
    [ -d "$dir" ] || continue
    pid="${dir##*-}"
    kill -0 "$pid" 2>/dev/null || rm -rf "$dir"
  done
}
