import LikenessGlue
import XCTest

/// Vertex normals for the meshes the core returns.
final class MeshNormalsTests: XCTestCase {
    func testCounterClockwiseTriangleFacesTheViewer() {
        let vertices: [Float] = [0, 0, 0, 1, 0, 0, 0, 1, 0]
        let normals = MeshNormals.compute(vertices: vertices, triangles: [0, 1, 2])
        XCTAssertEqual(normals, [0, 0, 1, 0, 0, 1, 0, 0, 1])
    }

    func testSharedVertexAveragesByArea() {
        // Two triangles around vertex 0: a big one facing +z, a small one facing +x.
        let vertices: [Float] = [0, 0, 0, 2, 0, 0, 0, 2, 0, 0, 1, 0, 0, 0, 1]
        let normals = MeshNormals.compute(vertices: vertices, triangles: [0, 1, 2, 0, 3, 4])
        let x = normals[0], y = normals[1], z = normals[2]
        XCTAssertEqual(x * x + y * y + z * z, 1, accuracy: 1e-6)
        XCTAssertGreaterThan(z, x)
        XCTAssertGreaterThan(x, 0)
    }

    func testLooseAndDegenerateVerticesFaceTheViewer() {
        let vertices: [Float] = [0, 0, 0, 1, 1, 1, 2, 2, 2, 5, 5, 5]
        let normals = MeshNormals.compute(vertices: vertices, triangles: [0, 1, 2, 0, 1, 9])
        XCTAssertEqual(normals, [0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1])
    }
}
