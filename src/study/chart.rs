//! The study charts, drawn with plotters into PNG files (and, for the HTML report, into SVG
//! text with the same drawing code):
//! - `ablation.png`: per-participant grouped bars of task time, ray-casting vs manual (the
//!   chart of the paper's Fig. 7). A missing bar (a trial that did not complete) is marked with
//!   a red cross; in a what-if, black outlines show the baseline times.
//! - `sweep.png`: mean task time per mode against the value of a swept parameter.
//!
//! Notes (the what-if kind and parameter values, the synthetic-data note) are printed under the
//! chart.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::StudyError;
use super::report::ParticipantTimes;
use super::whatif::Sweep;

const FONT: &str = "grove-sans";
/// The ray-casting bar colour.
pub const RAY: RGBColor = RGBColor(46, 134, 193);
/// The manual bar colour.
pub const MANUAL: RGBColor = RGBColor(230, 126, 34);
/// The colour of the mark of a missing bar.
pub const MISSING: RGBColor = RGBColor(200, 30, 30);

fn register_font() {
    // Registering twice is harmless; the bytes are egui's bundled Ubuntu Light font.
    let _ = plotters::style::register_font(FONT, FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT);
}

/// A drawing error as one line.
fn err(e: impl std::fmt::Display) -> String {
    e.to_string()
}

/// Runs `draw` on a PNG file of `width` × `height` pixels; errors name the file.
fn to_png(
    path: &Path,
    width: u32,
    height: u32,
    draw: impl FnOnce(&DrawingArea<BitMapBackend<'_>, Shift>) -> Result<(), String>,
) -> Result<(), StudyError> {
    register_font();
    let root = BitMapBackend::new(path, (width, height)).into_drawing_area();
    draw(&root)
        .and_then(|()| root.present().map_err(err))
        .map_err(|reason| StudyError::Chart { what: path.display().to_string(), reason })
}

/// Runs `draw` on an SVG document of `width` × `height` pixels and returns its text; the text
/// names a font every browser has.
fn to_svg(
    width: u32,
    height: u32,
    draw: impl FnOnce(&DrawingArea<SVGBackend<'_>, Shift>) -> Result<(), String>,
) -> Result<String, StudyError> {
    register_font();
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, (width, height)).into_drawing_area();
        draw(&root)
            .and_then(|()| root.present().map_err(err))
            .map_err(|reason| StudyError::Chart { what: "SVG chart".into(), reason })?;
    }
    Ok(text.replace(&format!("font-family=\"{FONT}\""), "font-family=\"sans-serif\""))
}

/// Splits off a strip at the bottom for the notes and writes them there.
fn with_notes<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    notes: &[String],
) -> Result<DrawingArea<DB, Shift>, String> {
    let (_, h) = root.dim_in_pixel();
    let strip = 8 + 22 * notes.len() as i32;
    let (main, foot) = root.split_vertically((h as i32 - strip).max(1));
    for (i, n) in notes.iter().enumerate() {
        foot.draw(&Text::new(n.clone(), (16, 4 + 22 * i as i32), (FONT, 17).into_font().color(&BLACK))).map_err(err)?;
    }
    Ok(main)
}

/// Draws the grouped bar chart of task times to a PNG file of `width` × `height` pixels.
/// `baseline`, when given, draws each participant's baseline times as outlines.
pub fn ablation_chart(
    path: &Path,
    rows: &[ParticipantTimes],
    baseline: Option<&[ParticipantTimes]>,
    title: &str,
    notes: &[String],
    width: u32,
    height: u32,
) -> Result<(), StudyError> {
    to_png(path, width, height, |root| draw_ablation(root, rows, baseline, title, notes))
}

/// [`ablation_chart`] as the text of an SVG document.
pub fn ablation_svg(
    rows: &[ParticipantTimes],
    baseline: Option<&[ParticipantTimes]>,
    title: &str,
    notes: &[String],
    width: u32,
    height: u32,
) -> Result<String, StudyError> {
    to_svg(width, height, |root| draw_ablation(root, rows, baseline, title, notes))
}

fn draw_ablation<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    rows: &[ParticipantTimes],
    baseline: Option<&[ParticipantTimes]>,
    title: &str,
    notes: &[String],
) -> Result<(), String> {
    root.fill(&WHITE).map_err(err)?;
    let main = with_notes(root, notes)?;
    let base_of = |p: &str| baseline.and_then(|b| b.iter().find(|r| r.participant == p));
    let max = rows
        .iter()
        .flat_map(|r| {
            [
                r.ray_casting_s,
                r.manual_s,
                base_of(&r.participant).and_then(|b| b.ray_casting_s),
                base_of(&r.participant).and_then(|b| b.manual_s),
            ]
        })
        .flatten()
        .fold(1.0f64, f64::max)
        * 1.2;
    let n = rows.len().max(1);
    let mut chart = ChartBuilder::on(&main)
        .caption(title, (FONT, 24))
        .margin(16)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d(-0.5f64..n as f64 - 0.5, 0f64..max)
        .map_err(err)?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(n.min(40))
        .x_label_formatter(&|x| {
            // Bars are centred on whole numbers; other tick positions get no label.
            if (x - x.round()).abs() > 1e-6 || *x < 0.0 {
                return String::new();
            }
            rows.get(x.round() as usize).map(|r| r.participant.clone()).unwrap_or_default()
        })
        .x_desc("Participant")
        .y_desc("Task time (s)")
        .label_style((FONT, 16))
        .axis_desc_style((FONT, 20))
        .draw()
        .map_err(err)?;
    let bar = |i: usize, offset: f64, v: f64, c: RGBColor| {
        Rectangle::new([(i as f64 + offset, 0.0), (i as f64 + offset + 0.38, v)], c.filled())
    };
    chart
        .draw_series(rows.iter().enumerate().filter_map(|(i, r)| r.ray_casting_s.map(|v| bar(i, -0.4, v, RAY))))
        .map_err(err)?
        .label("ray-casting")
        .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 14, y + 6)], RAY.filled()));
    chart
        .draw_series(rows.iter().enumerate().filter_map(|(i, r)| r.manual_s.map(|v| bar(i, 0.02, v, MANUAL))))
        .map_err(err)?
        .label("manual")
        .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 14, y + 6)], MANUAL.filled()));
    // A missing bar: a red cross where the bar would stand, so that no bar silently disappears.
    let h = max * 0.06;
    let crosses: Vec<(usize, f64)> = rows
        .iter()
        .enumerate()
        .flat_map(|(i, r)| {
            [(r.ray_casting_s.is_none()).then_some((i, -0.4)), (r.manual_s.is_none()).then_some((i, 0.02))]
        })
        .flatten()
        .collect();
    if !crosses.is_empty() {
        chart
            .draw_series(crosses.iter().flat_map(|&(i, o)| {
                let (x0, x1) = (i as f64 + o + 0.04, i as f64 + o + 0.34);
                [
                    PathElement::new(vec![(x0, 0.0), (x1, h)], MISSING.stroke_width(4)),
                    PathElement::new(vec![(x0, h), (x1, 0.0)], MISSING.stroke_width(4)),
                ]
            }))
            .map_err(err)?
            .label("missing: trial not completed")
            .legend(move |(x, y)| PathElement::new(vec![(x, y - 6), (x + 14, y + 6)], MISSING.stroke_width(3)));
    }
    if let Some(b) = baseline {
        let outline = |i: usize, o: f64, v: f64| {
            Rectangle::new([(i as f64 + o, 0.0), (i as f64 + o + 0.38, v)], BLACK.stroke_width(2))
        };
        chart
            .draw_series(
                rows.iter()
                    .enumerate()
                    .flat_map(|(i, r)| {
                        let b = b.iter().find(|x| x.participant == r.participant);
                        [
                            b.and_then(|b| b.ray_casting_s).map(|v| outline(i, -0.4, v)),
                            b.and_then(|b| b.manual_s).map(|v| outline(i, 0.02, v)),
                        ]
                    })
                    .flatten(),
            )
            .map_err(err)?
            .label("baseline (default settings)")
            .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 14, y + 6)], BLACK.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .label_font((FONT, 18))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    Ok(())
}

/// Draws mean task time per mode against the swept value, with the default value marked.
pub fn sweep_chart(path: &Path, sweep: &Sweep, notes: &[String], width: u32, height: u32) -> Result<(), StudyError> {
    to_png(path, width, height, |root| draw_sweep(root, sweep, notes))
}

/// [`sweep_chart`] as the text of an SVG document.
pub fn sweep_svg(sweep: &Sweep, notes: &[String], width: u32, height: u32) -> Result<String, StudyError> {
    to_svg(width, height, |root| draw_sweep(root, sweep, notes))
}

fn draw_sweep<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    sweep: &Sweep,
    notes: &[String],
) -> Result<(), String> {
    root.fill(&WHITE).map_err(err)?;
    let main = with_notes(root, notes)?;
    let points = |mode: &str| -> Vec<(f64, f64)> {
        sweep
            .rows
            .iter()
            .filter_map(|r| Some((r.value.parse::<f64>().ok()?, r.modes.get(mode)?.what_if_mean_s?)))
            .collect()
    };
    let xs: Vec<f64> = sweep.rows.iter().filter_map(|r| r.value.parse::<f64>().ok()).collect();
    let (lo, hi) = xs.iter().fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(*x), b.max(*x)));
    let (lo, hi) = if lo <= hi { (lo, hi) } else { (0.0, 1.0) };
    let pad = ((hi - lo) * 0.08).max(1e-3);
    let ymax = ["ray-casting", "manual"].iter().flat_map(|m| points(m)).map(|p| p.1).fold(1.0f64, f64::max) * 1.2;
    let mut chart = ChartBuilder::on(&main)
        .caption(format!("Mean task time against {} ({})", sweep.parameter, sweep.kind), (FONT, 24))
        .margin(16)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d((lo - pad)..(hi + pad), 0f64..ymax)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(sweep.parameter.as_str())
        .y_desc("Mean task time of completed trials (s)")
        .label_style((FONT, 16))
        .axis_desc_style((FONT, 20))
        .draw()
        .map_err(err)?;
    if let Ok(d) = sweep.default_value.parse::<f64>() {
        chart
            .draw_series([PathElement::new(vec![(d, 0.0), (d, ymax)], RGBColor(120, 120, 120).stroke_width(2))])
            .map_err(err)?;
        chart
            .draw_series([Text::new(
                format!("default {}", sweep.default_value),
                (d, ymax * 0.97),
                (FONT, 16).into_font().color(&BLACK),
            )])
            .map_err(err)?;
    }
    for (mode, colour) in [("ray-casting", RAY), ("manual", MANUAL)] {
        let pts = points(mode);
        chart
            .draw_series(LineSeries::new(pts.clone(), colour.stroke_width(3)))
            .map_err(err)?
            .label(mode)
            .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 14, y + 6)], colour.filled()));
        chart.draw_series(pts.iter().map(|p| Circle::new(*p, 6, colour.filled()))).map_err(err)?;
        // Where trials did not complete, say how many did: the mean is over fewer trials, or
        // there is no point at all.
        let labels: Vec<(f64, f64, String)> = sweep
            .rows
            .iter()
            .filter_map(|r| {
                let x = r.value.parse::<f64>().ok()?;
                let c = r.modes.get(mode)?;
                let (done, all) = (r.completed.get(mode).copied().unwrap_or(0), c.pairs + c.unpaired);
                (done < all).then(|| {
                    (x, c.what_if_mean_s.map_or(ymax * 0.04, |y| y + ymax * 0.03), format!("{done}/{all} completed"))
                })
            })
            .collect();
        chart
            .draw_series(
                labels.into_iter().map(|(x, y, t)| Text::new(t, (x, y), (FONT, 15).into_font().color(&colour))),
            )
            .map_err(err)?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .label_font((FONT, 18))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    Ok(())
}
