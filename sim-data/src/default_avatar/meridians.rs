//! Where the head's vertices go, and the plane they are triangulated in.
//!
//! The skin beyond the face is the surface `S(γ, ψ)` of [`super::head`]
//! (`γ` from the crown to [`super::head::BOTTOM_Y`], `ψ` the azimuth). Its
//! vertices lie on rings at equal steps of arc length down every meridian
//! (`σ`, the fraction of the meridian's length from the crown), and points
//! on a ring are equally spaced. Equal steps in `γ` instead would bunch
//! the rings where the rays meet the skin squarely and spread them where
//! they graze it (the jaw's underside, the neck, the shoulders).
//!
//! They are triangulated in a plane where the skin's metric is nearly a
//! multiple of the plane's, so triangles there keep their shape on the
//! skin. For a surface of revolution with ring circumference `C(s)` at arc
//! length `s`, the map `(s, ψ) ↦ R(s) (sin ψ, cos ψ)` with
//! `d ln R / ds = 2π / C(s)` is conformal (the Mercator construction); the
//! head is nearly one, so [`Meridians::plane`] takes `s = σ L̄` (`L̄` the
//! mean meridian length) and `C` the mean circumference of the ring at
//! `σ`. Near the crown `R ≈ s`.

use std::f64::consts::TAU;

/// Meridians sampled per turn of the azimuth.
pub const AZIMUTHS: usize = 180;
/// Arc-length samples per meridian.
const STEPS: usize = 400;
/// Samples of the ring circumference down the meridians.
const RING_SAMPLES: usize = 200;

/// The head's meridians, tabulated: each one's arc length over its
/// parameter `τ = γ/γ_max(ψ)`, and the conformal radius over `σ`.
pub struct Meridians {
    /// `cumulative[k][i]`: arc length of meridian `k` from the crown to
    /// `τ = i/STEPS` (m).
    cumulative: Vec<Vec<f64>>,
    /// Conformal radius `R` at `σ = i/RING_SAMPLES` (m).
    radius: Vec<f64>,
    /// Mean meridian length `L̄` (m).
    pub length: f64,
}

fn az_index(psi: f64) -> (usize, usize, f64) {
    let s = psi.rem_euclid(TAU) / TAU * AZIMUTHS as f64;
    let k = s.floor() as usize % AZIMUTHS;
    (k, (k + 1) % AZIMUTHS, s.fract())
}

impl Meridians {
    /// Tabulates the meridians of the surface `surface(τ, ψ)`.
    pub fn new(surface: &dyn Fn(f64, f64) -> glam::DVec3) -> Meridians {
        let cumulative: Vec<Vec<f64>> = (0..AZIMUTHS)
            .map(|k| {
                let psi = TAU * k as f64 / AZIMUTHS as f64;
                let at = |i: usize| surface(i as f64 / STEPS as f64, psi);
                let mut c = vec![0.0; STEPS + 1];
                for i in 0..STEPS {
                    c[i + 1] = c[i] + at(i).distance(at(i + 1));
                }
                c
            })
            .collect();
        let length = cumulative.iter().map(|c| c[STEPS]).sum::<f64>() / AZIMUTHS as f64;
        let mut m = Meridians {
            cumulative,
            radius: Vec::new(),
            length,
        };
        let circumference: Vec<f64> = (0..=RING_SAMPLES)
            .map(|i| m.circumference(surface, i as f64 / RING_SAMPLES as f64))
            .collect();
        let ds = length / RING_SAMPLES as f64;
        let mut radius = vec![0.0; RING_SAMPLES + 1];
        radius[1] = circumference[1] / TAU;
        for i in 1..RING_SAMPLES {
            let c = 0.5 * (circumference[i] + circumference[i + 1]);
            radius[i + 1] = radius[i] * (TAU * ds / c).exp();
        }
        m.radius = radius;
        m
    }

    /// `τ` of meridian `k` at arc-length fraction `sigma`.
    fn tau_on(&self, k: usize, sigma: f64) -> f64 {
        let c = &self.cumulative[k];
        let target = sigma.clamp(0.0, 1.0) * c[STEPS];
        let i = c.partition_point(|a| *a < target).clamp(1, STEPS);
        let f = (target - c[i - 1]) / (c[i] - c[i - 1]).max(1e-12);
        (i as f64 - 1.0 + f.clamp(0.0, 1.0)) / STEPS as f64
    }

    /// Arc-length fraction of meridian `k` at parameter `tau`.
    fn sigma_on(&self, k: usize, tau: f64) -> f64 {
        let c = &self.cumulative[k];
        let s = tau.clamp(0.0, 1.0) * STEPS as f64;
        let i = (s.floor() as usize).min(STEPS - 1);
        (c[i] + (s - i as f64) * (c[i + 1] - c[i])) / c[STEPS]
    }

    /// The parameter `τ` at arc-length fraction `sigma` and azimuth `psi`.
    pub fn tau(&self, sigma: f64, psi: f64) -> f64 {
        let (a, b, f) = az_index(psi);
        self.tau_on(a, sigma) * (1.0 - f) + self.tau_on(b, sigma) * f
    }

    /// The arc-length fraction `σ` at parameter `tau` and azimuth `psi`.
    pub fn sigma(&self, tau: f64, psi: f64) -> f64 {
        let (a, b, f) = az_index(psi);
        self.sigma_on(a, tau) * (1.0 - f) + self.sigma_on(b, tau) * f
    }

    /// Length of the ring at arc-length fraction `sigma` (m).
    pub fn circumference(&self, surface: &dyn Fn(f64, f64) -> glam::DVec3, sigma: f64) -> f64 {
        let at = |j: usize| {
            let psi = TAU * j as f64 / 72.0;
            surface(self.tau(sigma, psi), psi)
        };
        (0..72).map(|j| at(j).distance(at(j + 1))).sum()
    }

    /// The point at `(σ, ψ)` in the triangulation's plane: `R(σ) (sin ψ,
    /// cos ψ)`, `R` interpolated in `ln R` between samples (linear in `σ`
    /// before the first).
    pub fn plane(&self, sigma: f64, psi: f64) -> [f64; 2] {
        let s = sigma.clamp(0.0, 1.0) * RING_SAMPLES as f64;
        let r = if s < 1.0 {
            self.radius[1] * s
        } else {
            let i = (s.floor() as usize).min(RING_SAMPLES - 1);
            let f = s - i as f64;
            (self.radius[i].ln() * (1.0 - f) + self.radius[i + 1].ln() * f).exp()
        };
        [r * psi.sin(), r * psi.cos()]
    }
}
