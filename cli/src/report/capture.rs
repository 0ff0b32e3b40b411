//! "The capture": the session's stream replayed through the guided capture
//! (`likeness::capture::replay`, the state machine the app runs), drawn
//! as a timeline per face region with each capture's quality flags, each
//! prompt's requested weight around its detected peak (and the true peak
//! where the simulator knows it), and the neutral scan rendered.

use super::charts::{self, Area, ChartResult, EBFR, FONT, MARK, PAPER};
use super::colour_map::SKIN;
use super::html::{self, Section, escape};
use super::output::Files;
use super::rasterizer::{FrontView, Mesh, render};
use likeness::capture::guided_capture::{CaptureQuality, GuidedCaptureConfig, Step};
use likeness::capture::prompt_order::PROMPT_ORDER;
use likeness::capture::replay::{ReplayReport, ReplayedStep, replay_session};
use likeness::{Blendshape, Session};
use plotters::prelude::*;
use std::fmt::Write;

/// The face regions of the timeline, as the app groups its prompts: a
/// name, a file name, and the name prefixes of ARKit's shapes in it.
const REGIONS: [(&str, &str, &[&str]); 6] = [
    ("brows", "brows", &["brow"]),
    ("eyes", "eyes", &["eye"]),
    ("cheeks & nose", "cheeks-nose", &["cheek", "nose"]),
    ("jaw", "jaw", &["jaw"]),
    ("mouth", "mouth", &["mouth"]),
    ("tongue", "tongue", &["tongue"]),
];

/// The size of the neutral scan's picture.
pub const NEUTRAL_SIZE: (u32, u32) = (360, 440);

/// Seconds of stream shown before and after each detected peak.
const WINDOW: (f64, f64) = (1.5, 1.0);

/// The region (index into [`REGIONS`]) of `shape`.
fn region_of(shape: Blendshape) -> usize {
    REGIONS
        .iter()
        .position(|(_, _, prefixes)| prefixes.iter().any(|p| shape.name().starts_with(p)))
        .unwrap_or(REGIONS.len() - 1)
}

/// The quality flags of a step in words (empty when clean).
fn flags(quality: &CaptureQuality) -> Vec<String> {
    let mut out = Vec::new();
    if quality.weak {
        out.push("weak".to_string());
    }
    if let Some(other) = quality.dominated_by {
        out.push(format!("dominated by {other}"));
    }
    if quality.tracking_lost {
        out.push("tracking lost".to_string());
    }
    if let Some(shape) = quality.high_rest {
        out.push(format!("rests high on {shape}"));
    }
    out
}

/// The marker colour of a step: green when clean, orange when flagged,
/// red when tracking was lost.
fn step_colour(step: &ReplayedStep) -> RGBColor {
    if step.quality.tracking_lost {
        MARK
    } else if step.quality.is_clean() {
        PAPER
    } else {
        EBFR
    }
}

/// The capture section: replays the stream, draws the timeline, the
/// per-region weights and the neutral scan, and lists what was flagged.
pub fn section(
    session: &Session,
    files: &mut Files,
) -> Result<Section, Box<dyn std::error::Error>> {
    let report = replay_session(session.clone(), GuidedCaptureConfig::default())?;
    let time = |frame: u64| session.frames.get(frame as usize).map(|f| f.timestamp);
    let mut body = String::new();
    let captured = report.captured();
    let _ = write!(
        body,
        "<p>{} frames ({:.0} s at {} fps) replayed through the guided capture: {} of {} steps captured, {} skipped.",
        report.frames,
        session.duration(),
        session.frame_rate,
        captured,
        report.steps.len(),
        report.skipped()
    );
    if let Some(max) = report.max_frame_error() {
        let _ = write!(
            body,
            " Detected peaks lie at most {max} frame{} from the true peaks the simulator knows (test expressions: {}).",
            if max == 1 { "" } else { "s" },
            report
                .max_test_frame_error()
                .map_or("–".to_string(), |m| m.to_string())
        );
    }
    body.push_str("</p>");

    let timeline = timeline_svg(session, &report)?;
    files.add("capture/timeline.svg", timeline.into_bytes());
    body.push_str(&html::figure(
        "capture/timeline.svg",
        TIMELINE_SIZE.0,
        TIMELINE_SIZE.1,
        "capture timeline",
        "Every step at the moment it was captured, one lane per face region: green clean, \
         orange flagged (weak, dominated by another shape, resting high), red tracking lost \
         near the capture; red ticks in the top lane are frames where the face was not tracked.",
    ));

    body.push_str("<h3>Each prompt's requested weight</h3><p class=\"note\">The weight of the requested shape from 1.5 s before to 1 s after the detected peak (dot); the dashed red line is the true peak where the simulator knows it. A title in orange names the capture's flags.</p>");
    for (r, (name, file, _)) in REGIONS.iter().enumerate() {
        let steps: Vec<&ReplayedStep> = PROMPT_ORDER
            .iter()
            .filter(|s| region_of(**s) == r)
            .filter_map(|s| report.steps.iter().find(|x| x.step == Step::Expression(*s)))
            .collect();
        if steps.is_empty() {
            continue;
        }
        let (svg, size) = weights_svg(session, &steps, &time)?;
        let path = format!("capture/{file}.svg");
        files.add(path.clone(), svg.into_bytes());
        let caption = format!(
            "{}: {} prompt{}",
            escape(name),
            steps.len(),
            if steps.len() == 1 { "" } else { "s" }
        );
        body.push_str(&html::figure(&path, size.0, size.1, name, &caption));
    }

    body.push_str("<h3>Flags and skips</h3>");
    body.push_str(&flag_table(&report));

    let neutral: Vec<glam::DVec3> = session.neutral.iter().map(|p| p.as_dvec3()).collect();
    let colours = vec![SKIN; neutral.len()];
    let view = FrontView::framing(&neutral, NEUTRAL_SIZE.0, NEUTRAL_SIZE.1, 0.04);
    let image = render(
        &[Mesh {
            positions: &neutral,
            triangles: session.topology.triangles(),
            colours: &colours,
        }],
        &view,
    );
    files.add("capture/neutral-scan.png", image.png()?);
    body.push_str("<h3>The neutral scan</h3>");
    body.push_str(&html::figure(
        "capture/neutral-scan.png",
        NEUTRAL_SIZE.0,
        NEUTRAL_SIZE.1,
        "neutral scan",
        &format!(
            "The neutral scan B₀ ({} vertices), from the front: every personalized shape starts here.",
            neutral.len()
        ),
    ));
    Ok(Section {
        id: "capture",
        title: "The capture".to_string(),
        body,
    })
}

/// The table of steps that were flagged or skipped, or a sentence saying
/// there were none.
fn flag_table(report: &ReplayReport) -> String {
    let rows: Vec<String> = report
        .steps
        .iter()
        .filter(|s| s.frame.is_none() || !s.quality.is_clean())
        .map(|s| {
            let what = match s.frame {
                None => "<span class=\"bad\">skipped</span>".to_string(),
                Some(_) => format!(
                    "<span class=\"flag\">{}</span>",
                    escape(&flags(&s.quality).join(", "))
                ),
            };
            let cell = |v: Option<String>| {
                format!("<td class=\"num\">{}</td>", v.unwrap_or_else(|| "–".into()))
            };
            format!(
                "<tr><td>{}</td>{}{}{}<td>{what}</td></tr>",
                escape(&s.name),
                cell(s.frame.map(|f| f.to_string())),
                cell(s.true_frame.map(|f| f.to_string())),
                cell(s.frame_error().map(|e| format!("{e:+}"))),
            )
        })
        .collect();
    if rows.is_empty() {
        return "<p>No step was flagged or skipped.</p>".to_string();
    }
    html::table(
        "flags",
        &["step", "captured frame", "true peak", "offset", "flags"],
        &rows,
    )
}

/// The timeline's size in pixels.
pub const TIMELINE_SIZE: (u32, u32) = (1100, 300);

/// Lanes of the timeline from the top: untracked frames, the neutral
/// scan, the regions, the tests.
fn lane_names() -> Vec<String> {
    let mut names = vec!["untracked".to_string(), "neutral".to_string()];
    names.extend(REGIONS.iter().map(|r| r.0.to_string()));
    names.push("tests".to_string());
    names
}

/// The lane (0 at the top) of a step.
fn lane_of(step: Step) -> usize {
    match step {
        Step::Neutral => 1,
        Step::Expression(shape) => 2 + region_of(shape),
        Step::Test(_) => 2 + REGIONS.len(),
    }
}

/// The timeline: a marker per captured step at its time, in its lane,
/// coloured by its flags; untracked frames as ticks.
fn timeline_svg(session: &Session, report: &ReplayReport) -> ChartResult<String> {
    let names = lane_names();
    let lanes = names.len();
    let end = session.frames.last().map_or(1.0, |f| f.timestamp).max(1.0);
    let start = session.frames.first().map_or(0.0, |f| f.timestamp);
    // y grows upwards: lane 0 is drawn at the top.
    let y = move |lane: usize| (lanes - 1 - lane) as f64;
    charts::svg(TIMELINE_SIZE.0, TIMELINE_SIZE.1, |root| {
        let mut chart = ChartBuilder::on(root)
            .margin(12)
            .x_label_area_size(36)
            .y_label_area_size(112)
            .build_cartesian_2d(start..end, -0.6..lanes as f64 - 0.4)?;
        let label = |v: &f64| {
            let lane = lanes as f64 - 1.0 - v.round();
            if (v - v.round()).abs() < 1e-6 && lane >= 0.0 {
                names.get(lane as usize).cloned().unwrap_or_default()
            } else {
                String::new()
            }
        };
        chart
            .configure_mesh()
            .y_labels(lanes)
            .y_label_formatter(&label)
            .x_desc("time (s)")
            .label_style((FONT, 15))
            .axis_desc_style((FONT, 16))
            .light_line_style(WHITE)
            .draw()?;
        let untracked = session.frames.iter().filter(|f| !f.tracked);
        chart
            .draw_series(untracked.map(|f| {
                PathElement::new(
                    vec![(f.timestamp, y(0) - 0.3), (f.timestamp, y(0) + 0.3)],
                    MARK.stroke_width(1),
                )
            }))?
            .label("untracked frame")
            .legend(|(x, y)| PathElement::new(vec![(x + 5, y - 6), (x + 5, y + 6)], MARK));
        for (colour, name) in [(PAPER, "clean"), (EBFR, "flagged"), (MARK, "tracking lost")] {
            let points = report.steps.iter().filter(|s| step_colour(s) == colour);
            let at: Vec<(f64, f64)> = points
                .filter_map(|s| {
                    Some((
                        session.frames.get(s.frame? as usize)?.timestamp,
                        y(lane_of(s.step)),
                    ))
                })
                .collect();
            chart
                .draw_series(at.iter().map(|p| Circle::new(*p, 4, colour.filled())))?
                .label(name)
                .legend(move |(x, y)| Circle::new((x + 5, y), 4, colour.filled()));
        }
        charts::legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        Ok(())
    })
}

/// Small charts of the requested weight around each step's detected
/// peak, six to a row; the SVG and its size.
fn weights_svg(
    session: &Session,
    steps: &[&ReplayedStep],
    time: &dyn Fn(u64) -> Option<f64>,
) -> ChartResult<(String, (u32, u32))> {
    const COLUMNS: usize = 6;
    const CELL: (u32, u32) = (183, 140);
    let rows = steps.len().div_ceil(COLUMNS);
    let size = (CELL.0 * COLUMNS as u32, CELL.1 * rows as u32);
    let svg = charts::svg(size.0, size.1, |root| {
        let cells = root.split_evenly((rows, COLUMNS));
        for (step, cell) in steps.iter().zip(&cells) {
            weight_chart(session, step, time, cell)?;
        }
        Ok(())
    })?;
    Ok((svg, size))
}

/// One step's chart: the requested weight from [`WINDOW`] before to after
/// its detected peak (or its true peak when skipped), in seconds from it.
fn weight_chart(
    session: &Session,
    step: &ReplayedStep,
    time: &dyn Fn(u64) -> Option<f64>,
    area: &Area<'_>,
) -> ChartResult<()> {
    let Step::Expression(shape) = step.step else {
        return Ok(());
    };
    let flagged = flags(&step.quality);
    let (title, colour) = match (step.frame, flagged.is_empty()) {
        (None, _) => (format!("{} · skipped", shape.name()), MARK),
        (Some(_), true) => (shape.name().to_string(), BLACK),
        (Some(_), false) => (format!("{} · {}", shape.name(), flagged.join(", ")), EBFR),
    };
    let centre = step.frame.or(step.true_frame).and_then(time);
    let mut chart = ChartBuilder::on(area)
        .margin(4)
        .margin_right(12)
        .caption(title, (FONT, 14).into_font().color(&colour))
        .x_label_area_size(18)
        .y_label_area_size(26)
        .build_cartesian_2d(-WINDOW.0..WINDOW.1, 0.0..1.05)?;
    chart
        .configure_mesh()
        .x_labels(3)
        .y_labels(3)
        .label_style((FONT, 12))
        .light_line_style(RGBColor(238, 238, 238))
        .draw()?;
    let Some(centre) = centre else {
        return Ok(());
    };
    let curve = session
        .frames
        .iter()
        .filter(|f| f.timestamp >= centre - WINDOW.0 && f.timestamp <= centre + WINDOW.1)
        .map(|f| (f.timestamp - centre, f64::from(f.weights.get(shape))));
    chart.draw_series(LineSeries::new(curve, charts::DT.stroke_width(2)))?;
    if let Some(t) = step.true_frame.and_then(time) {
        chart.draw_series(DashedLineSeries::new(
            [(t - centre, 0.0), (t - centre, 1.05)],
            4,
            3,
            MARK.stroke_width(1),
        ))?;
    }
    if let Some(frame) = step.frame.and_then(|f| session.frames.get(f as usize)) {
        let w = f64::from(frame.weights.get(shape));
        chart.draw_series([Circle::new(
            (frame.timestamp - centre, w),
            4,
            BLACK.filled(),
        )])?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_prompt_has_a_region_and_regions_follow_the_prompt_order() {
        let regions: Vec<usize> = PROMPT_ORDER.iter().map(|s| region_of(*s)).collect();
        assert_eq!(region_of(Blendshape::BrowInnerUp), 0);
        assert_eq!(region_of(Blendshape::NoseSneerLeft), 2);
        assert_eq!(region_of(Blendshape::TongueOut), 5);
        for r in 0..REGIONS.len() {
            assert!(regions.contains(&r), "region {r} has prompts");
        }
    }

    #[test]
    fn flags_in_words() {
        let quality = CaptureQuality {
            weak: true,
            dominated_by: Some(Blendshape::JawOpen),
            tracking_lost: false,
            high_rest: None,
        };
        assert_eq!(flags(&quality), vec!["weak", "dominated by jawOpen"]);
        assert!(flags(&CaptureQuality::default()).is_empty());
    }
}
