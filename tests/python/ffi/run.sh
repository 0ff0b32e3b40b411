#!/usr/bin/env bash
# The FFI's Python tests (tests/python/ffi/): builds the likeness-ffi
# library, the project's uniffi-bindgen and the likeness command, generates
# the Python bindings from the built library (UniFFI's library mode) into
# the target folder, and runs pytest on them.
#
#   tests/python/ffi/run.sh [--release] [pytest arguments...]
#
# The dev profile (the default) shares every compiled dependency with
# `cargo test --workspace`, so in CI only the adapter itself is new;
# --release measures the per-frame cost as shipped. Honours CARGO_TARGET_DIR.
set -euo pipefail
cd "$(dirname "$0")/../../.."
profile=dev
folder=debug
if [[ "${1:-}" == "--release" ]]; then
    profile=release
    folder=release
    shift
fi
case "$(uname -s)" in
    Darwin) library=liblikeness_ffi.dylib ;;
    *) library=liblikeness_ffi.so ;;
esac
target=$(cargo metadata --format-version 1 --no-deps |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')
cargo build --quiet --profile "$profile" -p likeness-cli
cargo build --quiet --profile "$profile" -p likeness-ffi -p uniffi-bindgen
# Generated bindings are build outputs: they live in the target folder.
out="$target/ffi-python-$profile"
rm -rf "$out"
mkdir -p "$out"
"$target/$folder/uniffi-bindgen" generate --library "$target/$folder/$library" \
    --language python --out-dir "$out" >/dev/null
# The generated module loads the library from its own folder.
ln -s "$target/$folder/$library" "$out/$library"
python3 -m pip install --quiet --disable-pip-version-check --root-user-action=ignore -r tests/python/ffi/requirements.txt
export LIKENESS_FFI_PYTHON="$out" LIKENESS_CLI="$target/$folder/likeness"
python3 -m pytest -q -p no:cacheprovider tests/python/ffi "$@"
