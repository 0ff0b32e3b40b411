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
    /// Corner radius of cards.
    static let cornerRadius: CGFloat = 16
    /// How long the capture screen's transitions take.
    static let animation = Animation.easeInOut(duration: 0.25)
}
