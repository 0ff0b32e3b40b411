import ARKit
import LikenessGlue
import XCTest

/// ARKit's face data into the core's flat arrays.
final class ARKitGlueTests: XCTestCase {
    private let first = ARFaceAnchor.BlendShapeLocation(rawValue: "first_L")
    private let second = ARFaceAnchor.BlendShapeLocation(rawValue: "second")
    private let third = ARFaceAnchor.BlendShapeLocation(rawValue: "third_R")

    func testWeightsFollowTheGivenKeyOrder() {
        let shapes: [ARFaceAnchor.BlendShapeLocation: NSNumber] = [first: 0.25, second: 0.5, third: 1]
        XCTAssertEqual(ARKitGlue.weights(from: shapes, keys: [third, first, second]), [1, 0.25, 0.5])
    }

    func testWeightsAreNeverMadeUpForAMissingKey() {
        let shapes: [ARFaceAnchor.BlendShapeLocation: NSNumber] = [first: 0.25]
        XCTAssertNil(ARKitGlue.weights(from: shapes, keys: [first, second]))
    }

    func testVerticesAreFlattenedXYZ() {
        let vertices: [SIMD3<Float>] = [SIMD3(1, 2, 3), SIMD3(-4, 5, -6)]
        XCTAssertEqual(ARKitGlue.flatten(vertices), [1, 2, 3, -4, 5, -6])
        XCTAssertEqual(ARKitGlue.flatten([]), [])
    }

    func testPackedVerticesAreLittleEndianFloatsXYZ() {
        let packed = ARKitGlue.packed([SIMD3(1, 2, 3), SIMD3(-4, 5, -6)])
        XCTAssertEqual(packed.count, 24)
        // 1.0 is 0x3F800000, least significant byte first.
        XCTAssertEqual(Array(packed.prefix(4)), [0x00, 0x00, 0x80, 0x3F])
        let floats = stride(from: 0, to: packed.count, by: 4).map { at in
            Float(bitPattern: packed[at..<at + 4].reversed().reduce(0) { $0 << 8 | UInt32($1) })
        }
        XCTAssertEqual(floats, [1, 2, 3, -4, 5, -6])
        XCTAssertEqual(ARKitGlue.packed([]).count, 0)
    }

    func testFlatValuesPackLikeVertices() {
        XCTAssertEqual(ARKitGlue.packed(flat: [1, 2, 3, -4, 5, -6]), ARKitGlue.packed([SIMD3(1, 2, 3), SIMD3(-4, 5, -6)]))
        XCTAssertEqual(ARKitGlue.packed(flat: []).count, 0)
    }

    func testTriangleIndicesBecomeUnsigned32Bit() {
        XCTAssertEqual(ARKitGlue.triangleIndices([0, 1, 1219, Int16.max]), [0, 1, 1219, 32767])
        // The bit pattern is kept: an index past Int16.max is not negative.
        XCTAssertEqual(ARKitGlue.triangleIndices([Int16(bitPattern: 40000)]), [40000])
    }
}
