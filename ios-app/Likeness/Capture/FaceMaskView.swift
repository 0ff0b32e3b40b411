import ARKit
import SceneKit
import SwiftUI

/// The front camera's picture with ARKit's tracked face mesh drawn over it,
/// so the person sees that the phone follows their face.
struct FaceMaskView: UIViewRepresentable {
    /// The running face-tracking session to show.
    let session: ARSession

    func makeCoordinator() -> FaceMaskRenderer {
        FaceMaskRenderer()
    }

    func makeUIView(context: Context) -> ARSCNView {
        let view = ARSCNView(frame: .zero)
        view.session = session
        view.delegate = context.coordinator
        view.automaticallyUpdatesLighting = true
        return view
    }

    func updateUIView(_ view: ARSCNView, context: Context) {
        if view.session !== session {
            view.session = session
        }
    }
}

/// Gives ARKit's face anchor a wireframe mask (`ARSCNFaceGeometry`) and keeps
/// it in step with the tracked face. Called on SceneKit's render thread.
final class FaceMaskRenderer: NSObject, ARSCNViewDelegate {
    func renderer(_ renderer: SCNSceneRenderer, nodeFor anchor: ARAnchor) -> SCNNode? {
        guard anchor is ARFaceAnchor,
              let device = renderer.device,
              let geometry = ARSCNFaceGeometry(device: device)
        else { return nil }
        let material = SCNMaterial()
        material.fillMode = .lines
        material.lightingModel = .constant
        material.diffuse.contents = UIColor.white
        material.transparency = Theme.maskTransparency
        geometry.materials = [material]
        return SCNNode(geometry: geometry)
    }

    func renderer(_ renderer: SCNSceneRenderer, didUpdate node: SCNNode, for anchor: ARAnchor) {
        guard let faceAnchor = anchor as? ARFaceAnchor,
              let geometry = node.geometry as? ARSCNFaceGeometry
        else { return }
        geometry.update(from: faceAnchor.geometry)
    }
}
