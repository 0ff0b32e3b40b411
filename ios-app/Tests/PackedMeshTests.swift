import LikenessGlue
import XCTest

/// The core's packed meshes checked before SceneKit reads them.
final class PackedMeshTests: XCTestCase {
    private func indices(_ values: [UInt32]) -> Data {
        var bytes: [UInt8] = []
        for value in values {
            withUnsafeBytes(of: value.littleEndian) { bytes.append(contentsOf: $0) }
        }
        return Data(bytes)
    }

    func testVectorsAreTwelveBytes() {
        XCTAssertEqual(PackedMesh.vectorCount(Data(count: 36)), 3)
        XCTAssertEqual(PackedMesh.vectorCount(Data()), 0)
        XCTAssertNil(PackedMesh.vectorCount(Data(count: 13)))
    }

    func testTrianglesMustBeWholeAndInRange() {
        XCTAssertEqual(PackedMesh.triangleCount(indices([0, 1, 2, 2, 1, 3]), vertexCount: 4), 2)
        XCTAssertNil(PackedMesh.triangleCount(indices([0, 1, 4]), vertexCount: 4), "index past the end")
        XCTAssertNil(PackedMesh.triangleCount(indices([0, 1]), vertexCount: 4), "not whole triangles")
        // Little-endian: 0x00010000 is 65536, far past the end.
        XCTAssertNil(PackedMesh.triangleCount(Data([0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0]), vertexCount: 4))
    }

    func testEmptyOrMisSizedTargetsAreLeftOut() {
        let full = Data(count: 24)
        let targets = [full, Data(), full, Data(count: 12)]
        XCTAssertEqual(PackedMesh.presentTargets(targets, vertexCount: 2), [0, 2])
        XCTAssertEqual(PackedMesh.presentTargets([Data()], vertexCount: 0), [])
    }
}
