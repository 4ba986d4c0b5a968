//! The study chart: per-participant grouped bars of task time, ray-casting vs manual
//! (the chart of the paper's Fig. 7), drawn with plotters into a PNG.

use std::path::Path;

use plotters::prelude::*;

use super::report::ParticipantTimes;

const FONT: &str = "grove-sans";

fn register_font() {
    // Registering twice is harmless; the bytes are egui's bundled Ubuntu Light font.
    let _ = plotters::style::register_font(FONT, FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT);
}

/// Draws the grouped bar chart of task times to a PNG file of `width` × `height` pixels.
pub fn ablation_chart(path: &Path, rows: &[ParticipantTimes], title: &str, width: u32, height: u32) -> anyhow::Result<()> {
    register_font();
    let err = |e: &dyn std::fmt::Display| anyhow::anyhow!("{}: {e}", path.display());
    let root = BitMapBackend::new(path, (width, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let max = rows.iter().flat_map(|r| [r.ray_casting_s, r.manual_s]).flatten().fold(1.0f64, f64::max) * 1.15;
    let n = rows.len().max(1);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (FONT, 26))
        .margin(16)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d(-0.5f64..n as f64 - 0.5, 0f64..max)
        .map_err(|e| err(&e))?;
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
        .map_err(|e| err(&e))?;
    let ray = RGBColor(46, 134, 193);
    let manual = RGBColor(230, 126, 34);
    let bar = |i: usize, offset: f64, v: f64, c: RGBColor| Rectangle::new([(i as f64 + offset, 0.0), (i as f64 + offset + 0.38, v)], c.filled());
    chart
        .draw_series(rows.iter().enumerate().filter_map(|(i, r)| r.ray_casting_s.map(|v| bar(i, -0.4, v, ray))))
        .map_err(|e| err(&e))?
        .label("ray-casting")
        .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 14, y + 6)], ray.filled()));
    chart
        .draw_series(rows.iter().enumerate().filter_map(|(i, r)| r.manual_s.map(|v| bar(i, 0.02, v, manual))))
        .map_err(|e| err(&e))?
        .label("manual")
        .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 14, y + 6)], manual.filled()));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .label_font((FONT, 18))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))?;
    Ok(())
}
