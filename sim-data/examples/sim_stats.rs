//! Prints a few statistics of a simulated session (development aid).
use likeness::Blendshape;
fn main() {
    let seed: u64 = std::env::args()
        .nth(1)
        .map(|s| s.parse().unwrap())
        .unwrap_or(1);
    let t = std::time::Instant::now();
    let s = likeness_sim::simulate_session(seed);
    eprintln!("simulated in {:?}", t.elapsed());
    let truth = s.truth.as_ref().unwrap();
    println!(
        "frames {} duration {:.1}s captures {} tests {}",
        s.frames.len(),
        s.duration(),
        s.captures.len(),
        s.tests.len()
    );
    let mut errs = vec![];
    for c in &s.captures {
        let tp = truth
            .peak_frames
            .iter()
            .find(|p| p.0 == c.prompt)
            .unwrap()
            .1;
        errs.push(c.frame.unwrap() as i64 - tp as i64);
    }
    println!("capture frame - true peak: {:?}", errs);
    let m = likeness_sim::face_mask::face_mask();
    let chin = m.landmarks.chin as usize;
    let jaw = &truth.blendshapes[Blendshape::JawOpen.index()];
    println!(
        "chin travel {:.1} mm",
        (jaw[chin] - truth.neutral[chin]).length() * 1000.0
    );
    for side in 0..2 {
        let b =
            &truth.blendshapes[[Blendshape::EyeBlinkLeft, Blendshape::EyeBlinkRight][side].index()];
        let gap = m.landmarks.upper_lid[side]
            .iter()
            .zip(&m.landmarks.lower_lid[side])
            .map(|(u, l)| (b[*u as usize] - b[*l as usize]).length())
            .fold(0.0f32, f32::max);
        println!("blink side {side} max lid gap {:.4} mm", gap * 1000.0);
    }
    let noise: f32 = truth
        .tests
        .iter()
        .zip(&s.tests)
        .map(|(a, b)| {
            a.iter()
                .zip(&b.vertices)
                .map(|(p, q)| (*p - *q).length_squared())
                .sum::<f32>()
                / a.len() as f32
        })
        .sum::<f32>()
        / s.tests.len() as f32;
    println!("test mesh rms noise {:.3} mm", noise.sqrt() * 1000.0);
}
