//! The 52 tracked weights of one frame, indexed by [`Blendshape`].

use super::blendshape::{BLENDSHAPE_COUNT, Blendshape};

/// One tracked value per ARKit blendshape, indexed by [`Blendshape`].
// Indexing: `Blendshape::index()` and positions in the array are always
// below BLENDSHAPE_COUNT, the array's length and that of `Blendshape::ALL`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Weights(pub [f32; BLENDSHAPE_COUNT]);

impl Weights {
    /// All weights zero: the neutral face.
    pub const ZERO: Weights = Weights([0.0; BLENDSHAPE_COUNT]);

    /// The weight of `shape`.
    pub fn get(&self, shape: Blendshape) -> f32 {
        self.0[shape.index()]
    }

    /// Sets the weight of `shape`.
    pub fn set(&mut self, shape: Blendshape, value: f32) {
        self.0[shape.index()] = value;
    }

    /// The shape with the largest weight (the first one on ties).
    pub fn dominant(&self) -> Blendshape {
        let mut best = 0;
        for (i, w) in self.0.iter().enumerate() {
            if *w > self.0[best] {
                best = i;
            }
        }
        Blendshape::ALL[best]
    }

    /// Iterates `(shape, weight)` in Apple's order.
    pub fn iter(&self) -> impl Iterator<Item = (Blendshape, f32)> + '_ {
        Blendshape::ALL.iter().map(|s| (*s, self.0[s.index()]))
    }
}

impl Default for Weights {
    fn default() -> Self {
        Weights::ZERO
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_index_by_shape() {
        let mut w = Weights::ZERO;
        w.set(Blendshape::JawOpen, 0.7);
        w.set(Blendshape::EyeBlinkLeft, 0.2);
        assert_eq!(w.get(Blendshape::JawOpen), 0.7);
        assert_eq!(w.dominant(), Blendshape::JawOpen);
        assert_eq!(w.iter().count(), 52);
    }
}
