//! People simulated on ARKit's own mesh (`../shared/arkit-face/`, never
//! committed; [`likeness_sim::arkit_face`]), simulated once per test
//! binary and shared by its tests. Where `../shared/` is absent (a fresh
//! clone) they are `None`, with a notice; under CI (`CI=true`), which has
//! it, its absence fails.

use likeness::Session;
use likeness::arkit::Blendshapes;
use likeness::avatar::personal_avatar::PersonInput;
use likeness::personalize::{Method, personalize};
use likeness_sim::arkit_face::{shared_arkit_face, shared_arkit_face_dir};
use likeness_sim::face_basis::FaceBasis;
use likeness_sim::{SAMPLE_GEOMETRY_WINDOW, SimulationOptions, simulate_session_with};
use std::sync::OnceLock;

/// Seeds of the people simulated on ARKit's mesh: the five.
pub const ARKIT_SEEDS: [u64; 5] = [1, 2, 3, 4, 5];

/// The seeds a study was given on its command line, or the five
/// ([`ARKIT_SEEDS`]) if none.
pub fn study_seeds() -> Result<Vec<u64>, std::num::ParseIntError> {
    let seeds: Vec<u64> = std::env::args()
        .skip(1)
        .map(|a| a.parse())
        .collect::<Result<_, _>>()?;
    Ok(if seeds.is_empty() {
        ARKIT_SEEDS.to_vec()
    } else {
        seeds
    })
}

/// One person on ARKit's mesh: the session, its template's shapes and the
/// person's personalized shapes.
pub struct ArkitPerson {
    /// The seed.
    pub seed: u64,
    /// The simulated session (meshes kept near captures, as the samples).
    pub session: Session,
    /// The session's template as blendshapes (ARKit's own).
    pub rig: Blendshapes,
    /// The person's shapes (the product's method).
    pub personalized: Blendshapes,
}

impl ArkitPerson {
    /// Person `seed` simulated on the mask `face` (either the simulator's
    /// or ARKit's), its meshes kept near captures as the samples, and
    /// personalized by the product's method.
    pub fn simulate(face: FaceBasis, seed: u64) -> ArkitPerson {
        let options = SimulationOptions {
            face,
            geometry_window: Some(SAMPLE_GEOMETRY_WINDOW),
            ..SimulationOptions::default()
        };
        let session = simulate_session_with(seed, options, &mut |_, _| {});
        let rig = session
            .template
            .blendshapes()
            .expect("the template's shapes");
        let personalized = personalize(&session, Method::DEFAULT)
            .expect("a simulated session personalizes")
            .shapes;
        ArkitPerson {
            seed,
            session,
            rig,
            personalized,
        }
    }

    /// What the avatar stage takes.
    pub fn input(&self) -> PersonInput<'_> {
        PersonInput {
            mask: &self.session.topology,
            rig: &self.rig,
            personalized: &self.personalized,
        }
    }
}

/// The five people on ARKit's mesh, personalized; `None` (with a notice on
/// stderr) where `../shared/` is absent.
pub fn arkit_people() -> Option<&'static [ArkitPerson]> {
    static PEOPLE: OnceLock<Option<Vec<ArkitPerson>>> = OnceLock::new();
    PEOPLE
        .get_or_init(|| {
            let Some(face) = shared_arkit_face() else {
                eprintln!(
                    "skipped: {} is absent (it is never committed)",
                    shared_arkit_face_dir().display()
                );
                return None;
            };
            Some(
                ARKIT_SEEDS
                    .iter()
                    .map(|&seed| ArkitPerson::simulate(FaceBasis::Arkit(face), seed))
                    .collect(),
            )
        })
        .as_deref()
}
