import SwiftUI

/// The few looks and sizes the screens share, in one place.
enum Theme {
    /// How strongly the tracked face mask shows over the camera picture.
    static let maskTransparency: CGFloat = 0.55
    /// Background of the cards drawn over the camera picture.
    static let cardBackground = Color.black.opacity(0.55)
    /// Background of the pause overlay.
    static let pauseBackground = Color.black.opacity(0.7)
    /// Side of the expression picture on the capture screen.
    static let previewSide: CGFloat = 120
    /// Height of the live mirror on the result screen.
    static let mirrorHeight: CGFloat = 320
    /// The radius (metres) an avatar's face is scaled to in the result's
    /// preview: about that of ARKit's face mask, which the mirror shows at
    /// its own size.
    static let faceRadius: Float = 0.1
    /// Corner radius of cards.
    static let cornerRadius: CGFloat = 16
    /// How long a passing notice (a dropped frame) stays up, in seconds.
    static let noticeSeconds: Double = 3
    /// Widest a weight bar on the review gets.
    static let weightBarWidth: CGFloat = 180
    /// How long the capture screen's transitions take.
    static let animation = Animation.easeInOut(duration: 0.25)
}
