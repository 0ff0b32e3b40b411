// swift-tools-version:5.9
// The Likeness core for iOS: the Rust static library as an XCFramework
// (LikenessFFIFramework, C module `likeness_ffiFFI`) and UniFFI's generated
// Swift over it (module LikenessFFI). Both are build outputs of
// build-xcframework.sh (see bindings/README.md); neither is committed.
import PackageDescription

let package = Package(
    name: "LikenessFFI",
    platforms: [.iOS(.v16)],
    products: [
        .library(name: "LikenessFFI", targets: ["LikenessFFI"]),
    ],
    targets: [
        .binaryTarget(
            name: "LikenessFFIFramework",
            path: "LikenessFFI.xcframework"
        ),
        .target(
            name: "LikenessFFI",
            dependencies: ["LikenessFFIFramework"],
            path: "Sources/LikenessFFI"
        ),
    ]
)
