#!/usr/bin/env bash
# Builds the Swift package in this folder: the likeness-ffi static library
# for iOS devices (aarch64-apple-ios) and simulators (aarch64-apple-ios-sim
# and x86_64-apple-ios, joined by lipo), UniFFI's Swift bindings with their
# C header and module map (the project's uniffi-bindgen, library mode), and
# LikenessFFI.xcframework (xcodebuild -create-xcframework).
#
#   bindings/apple/build-xcframework.sh                    # on a Mac with Xcode
#   bindings/apple/build-xcframework.sh --swift-only OUTDIR
#
# --swift-only runs anywhere (CI runs it on Linux): it writes
# likeness_ffi.swift, likeness_ffiFFI.h and likeness_ffiFFI.modulemap to
# OUTDIR from a host build of the library, to check the app's calls against
# the names UniFFI generates. The bindings depend only on the exported
# API, not on the target or the profile, so the host's dev build (which
# `cargo test` has already compiled) gives the same Swift as the iOS build.
# Honours CARGO_TARGET_DIR.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
cd "$here/../.."

say() { echo "build-xcframework.sh: $*" >&2; }
fail() {
    say "$*"
    exit 1
}

swift_only=""
case "${1:-}" in
    --swift-only)
        swift_only=${2:-}
        [[ -n "$swift_only" ]] || fail "usage: $0 --swift-only OUTDIR"
        ;;
    "") ;;
    *) fail "usage: $0 [--swift-only OUTDIR]" ;;
esac

command -v cargo >/dev/null || fail "cargo is needed (https://rustup.rs)"
target=$(cargo metadata --format-version 1 --no-deps |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')

# The project's own uniffi-bindgen: UniFFI's generator at the version the
# library is built with.
bindgen="$target/debug/uniffi-bindgen"

# Swift, header and module map of the library at $1 into folder $2.
generate_swift() {
    mkdir -p "$2"
    "$bindgen" generate --library "$1" --language swift --out-dir "$2" >/dev/null
    for file in likeness_ffi.swift likeness_ffiFFI.h likeness_ffiFFI.modulemap; do
        [[ -f "$2/$file" ]] || fail "uniffi-bindgen wrote no $file into $2"
    done
}

if [[ -n "$swift_only" ]]; then
    case "$(uname -s)" in
        Darwin) library=liblikeness_ffi.dylib ;;
        *) library=liblikeness_ffi.so ;;
    esac
    say "building likeness-ffi and uniffi-bindgen for the host (dev profile)"
    # Together, as tests/python/ffi/run.sh builds them: the same features,
    # so the same compiled artifacts.
    cargo build --quiet -p likeness-ffi -p uniffi-bindgen
    generate_swift "$target/debug/$library" "$swift_only"
    say "wrote likeness_ffi.swift, likeness_ffiFFI.h and likeness_ffiFFI.modulemap to $swift_only"
    exit 0
fi

[[ "$(uname -s)" == Darwin ]] || fail "the XCFramework needs macOS with Xcode; elsewhere use --swift-only OUTDIR"
command -v xcodebuild >/dev/null || fail "xcodebuild not found: install Xcode and run xcode-select"
command -v lipo >/dev/null || fail "lipo not found: install Xcode's command line tools"
command -v rustup >/dev/null || fail "rustup is needed to add the iOS targets"

device=aarch64-apple-ios
simulators=(aarch64-apple-ios-sim x86_64-apple-ios)
rustup target add "$device" "${simulators[@]}"
cargo build --quiet -p uniffi-bindgen
export IPHONEOS_DEPLOYMENT_TARGET=16.0

for triple in "$device" "${simulators[@]}"; do
    say "building the static library for $triple (profile phone: small, whole-program optimized)"
    cargo rustc --quiet --profile phone -p likeness-ffi --lib --target "$triple" --crate-type staticlib
    [[ -f "$target/$triple/phone/liblikeness_ffi.a" ]] ||
        fail "no $target/$triple/phone/liblikeness_ffi.a after the build"
done

work="$target/apple"
rm -rf "$work"
mkdir -p "$work/device" "$work/simulator" "$work/swift"
cp "$target/$device/phone/liblikeness_ffi.a" "$work/device/"
say "joining the simulator slices with lipo"
lipo -create \
    "$target/${simulators[0]}/phone/liblikeness_ffi.a" \
    "$target/${simulators[1]}/phone/liblikeness_ffi.a" \
    -output "$work/simulator/liblikeness_ffi.a"

say "generating the Swift bindings"
generate_swift "$work/device/liblikeness_ffi.a" "$work/swift"
# The C module in a folder of its own, as module.modulemap, so that it
# cannot collide with another framework's module map in Headers/.
headers="$work/headers/likeness_ffiFFI"
mkdir -p "$headers"
cp "$work/swift/likeness_ffiFFI.h" "$headers/"
cp "$work/swift/likeness_ffiFFI.modulemap" "$headers/module.modulemap"
mkdir -p "$here/Sources/LikenessFFI"
cp "$work/swift/likeness_ffi.swift" "$here/Sources/LikenessFFI/"

say "creating LikenessFFI.xcframework"
rm -rf "$here/LikenessFFI.xcframework"
xcodebuild -create-xcframework \
    -library "$work/device/liblikeness_ffi.a" -headers "$work/headers" \
    -library "$work/simulator/liblikeness_ffi.a" -headers "$work/headers" \
    -output "$here/LikenessFFI.xcframework" >/dev/null
say "done: $here (Package.swift, LikenessFFI.xcframework, Sources/LikenessFFI/likeness_ffi.swift)"
