//! The translation of a transferred shape (see the parent module's docs,
//! "Translation").
//!
//! Gradients determine a deformation up to one constant per connected
//! component. The solve pins one vertex per component; afterwards each
//! component is shifted by the constant `c` with
//!
//! ```text
//! mean_still(D + c) = σ · mean_still(M),
//! still = { i : ‖M_i‖ ≤ STILL_FRACTION · max_k ‖M_k‖ }  (else the i of least ‖M_i‖),
//! ```
//!
//! where `M` is the source motion `S_j − S₀` and `σ` the size ratio of the
//! target to the source.
//!
//! Indexing: as in the parent module, vertex indices are below the vertex
//! count `n` (checked triangles; `motion` and `delta` have `n` entries) and
//! component ids below the component count.

use super::{DeformationTransfer, STILL_FRACTION};
use glam::DVec3;

impl DeformationTransfer {
    /// Adds to each component the constant `c` with
    /// `mean_still(delta + c) = sigma · mean_still(motion)` (module docs).
    pub(super) fn fix_translation(&self, delta: &mut [DVec3], motion: &[DVec3], sigma: f64) {
        let n = self.component_count;
        let mut largest = vec![0.0_f64; n];
        let mut least = vec![(f64::INFINITY, 0_usize); n];
        for (v, m) in motion.iter().enumerate() {
            let (c, len) = (self.component[v] as usize, m.length());
            largest[c] = largest[c].max(len);
            if len < least[c].0 {
                least[c] = (len, v);
            }
        }
        let mut sum_motion = vec![DVec3::ZERO; n];
        let mut sum_delta = vec![DVec3::ZERO; n];
        let mut count = vec![0_usize; n];
        for (v, m) in motion.iter().enumerate() {
            let c = self.component[v] as usize;
            if m.length() <= STILL_FRACTION * largest[c] {
                sum_motion[c] += *m;
                sum_delta[c] += delta[v];
                count[c] += 1;
            }
        }
        let shift: Vec<DVec3> = (0..n)
            .map(|c| match count[c] {
                0 => sigma * motion[least[c].1] - delta[least[c].1],
                k => (sigma * sum_motion[c] - sum_delta[c]) / k as f64,
            })
            .collect();
        for (v, d) in delta.iter_mut().enumerate() {
            *d += shift[self.component[v] as usize];
        }
    }
}
