import SceneKit
import SwiftUI

/// A small SceneKit view showing one face mesh from the front, as in a mirror.
///
/// The caller owns `node` and changes its geometry directly (many times a
/// second for the live mirror), so SwiftUI does not re-render for every frame.
struct MeshView: UIViewRepresentable {
    /// The node whose geometry is shown; placed at the origin, facing +z.
    let node: SCNNode
    /// Redraw every display frame (the live mirror) rather than on changes.
    var continuous = false

    func makeUIView(context: Context) -> SCNView {
        let view = SCNView()
        view.scene = Self.scene(showing: node)
        view.autoenablesDefaultLighting = true
        view.backgroundColor = .clear
        view.isUserInteractionEnabled = false
        view.rendersContinuously = continuous
        view.antialiasingMode = .multisampling4X
        return view
    }

    func updateUIView(_ view: SCNView, context: Context) {
        view.rendersContinuously = continuous
    }

    /// A camera 45 cm in front of the face (ARKit's face coordinates: metres,
    /// +z towards the viewer), and the node mirrored left to right so the
    /// face moves like the person's reflection.
    private static func scene(showing node: SCNNode) -> SCNScene {
        let scene = SCNScene()
        let camera = SCNCamera()
        camera.fieldOfView = 30
        camera.zNear = 0.01
        camera.zFar = 2
        let cameraNode = SCNNode()
        cameraNode.camera = camera
        cameraNode.position = SCNVector3(0, 0, 0.45)
        scene.rootNode.addChildNode(cameraNode)
        node.scale = SCNVector3(-1, 1, 1)
        scene.rootNode.addChildNode(node)
        return scene
    }
}
