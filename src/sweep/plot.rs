//! The plot of a 1-D or 2-D sweep as SVG: one panel per kept reduction (up to six) against
//! the first varying setting; a second varying setting with few values gives one curve per
//! value, with many values (a Latin hypercube) a scatter of the two settings coloured by the
//! result.

use super::table::Csv;
use std::fmt::Write;

const PANEL_W: f64 = 360.0;
const PANEL_H: f64 = 240.0;
const MARGIN: [f64; 4] = [60.0, 20.0, 30.0, 45.0]; // left, right, top, bottom
const COLOURS: [&str; 8] = [
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf",
];

/// The settings that vary in a results CSV: the columns after `point` up to the first
/// `output:reduction` column with more than one distinct value.
pub fn varying_columns(csv: &Csv) -> Vec<usize> {
    (1..csv.header.len())
        .take_while(|&c| !csv.header[c].contains(':') && csv.header[c] != "status")
        .filter(|&c| {
            let first = csv.rows.first().map(|r| &r[c]);
            csv.rows.iter().any(|r| Some(&r[c]) != first)
        })
        .collect()
}

fn num(s: &str) -> f64 {
    match s {
        "true" => 1.0,
        "false" => 0.0,
        s => s.parse().unwrap_or(f64::NAN),
    }
}

fn range(xs: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for x in xs.filter(|x| x.is_finite()) {
        lo = lo.min(x);
        hi = hi.max(x);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    if hi - lo <= 1e-12 * hi.abs().max(1e-300) {
        let d = if lo == 0.0 { 1.0 } else { 0.05 * lo.abs() };
        return (lo - d, hi + d);
    }
    (lo, hi)
}

fn label(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if x.abs() >= 1e4 || x.abs() < 1e-3 {
        format!("{x:.3e}")
    } else {
        format!("{}", (x * 1e4).round() / 1e4)
    }
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The SVG plot of a results CSV, or `None` when it has not 1 or 2 varying settings.
pub fn plot_svg(csv: &Csv) -> Option<String> {
    let vary = varying_columns(csv);
    if vary.is_empty() || vary.len() > 2 {
        return None;
    }
    let reds: Vec<usize> = (1..csv.header.len())
        .filter(|&c| csv.header[c].contains(':'))
        .take(6)
        .collect();
    if reds.is_empty() {
        return None;
    }
    let cols = reds.len().min(2);
    let rows = reds.len().div_ceil(cols);
    let (w, h) = (PANEL_W * cols as f64, PANEL_H * rows as f64 + 30.0);
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    let xc = vary[0];
    let group: Option<usize> = vary.get(1).copied();
    // curves per value of the second setting when it has few values, else a scatter
    let mut groups: Vec<String> = Vec::new();
    if let Some(g) = group {
        for r in &csv.rows {
            if !groups.contains(&r[g]) {
                groups.push(r[g].clone());
            }
        }
    }
    let scatter = groups.len() > COLOURS.len();
    let title = match (group, scatter) {
        (None, _) => format!("sweep over {}", csv.header[xc]),
        (Some(g), false) => format!(
            "sweep over {} (one curve per {})",
            csv.header[xc], csv.header[g]
        ),
        (Some(g), true) => format!(
            "sweep over {} and {} (colour: result, blue low, red high)",
            csv.header[xc], csv.header[g]
        ),
    };
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"18\" text-anchor=\"middle\" font-size=\"13\">{}</text>",
        w / 2.0,
        esc(&title)
    );
    for (i, &rc) in reds.iter().enumerate() {
        let ox = PANEL_W * (i % cols) as f64;
        let oy = 30.0 + PANEL_H * (i / cols) as f64;
        let (x0, x1) = (ox + MARGIN[0], ox + PANEL_W - MARGIN[1]);
        let (y0, y1) = (oy + PANEL_H - MARGIN[3], oy + MARGIN[2]);
        let yc = if scatter {
            group.expect("scatter has a group")
        } else {
            rc
        };
        let xr = range(csv.rows.iter().map(|r| num(&r[xc])));
        let yr = range(csv.rows.iter().map(|r| num(&r[yc])));
        let px = |x: f64| x0 + (x - xr.0) / (xr.1 - xr.0) * (x1 - x0);
        let py = |y: f64| y0 + (y - yr.0) / (yr.1 - yr.0) * (y1 - y0);
        let _ = writeln!(
            s,
            "<rect x=\"{x0}\" y=\"{y1}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#444\"/>",
            x1 - x0,
            y0 - y1
        );
        for k in 0..=4 {
            let f = k as f64 / 4.0;
            let (xv, yv) = (xr.0 + f * (xr.1 - xr.0), yr.0 + f * (yr.1 - yr.0));
            let _ = writeln!(
                s,
                "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>\n<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{}</text>",
                px(xv),
                y0 + 14.0,
                label(xv),
                x0 - 4.0,
                py(yv) + 4.0,
                label(yv)
            );
        }
        let _ = writeln!(
            s,
            "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>",
            (x0 + x1) / 2.0,
            y0 + 30.0,
            esc(&csv.header[xc])
        );
        let ylabel = if scatter {
            format!("{} (colour: {})", csv.header[yc], csv.header[rc])
        } else {
            csv.header[rc].clone()
        };
        let _ = writeln!(
            s,
            "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\" font-weight=\"bold\">{}</text>",
            (x0 + x1) / 2.0,
            y1 - 6.0,
            esc(&ylabel)
        );
        if scatter {
            let cr = range(csv.rows.iter().map(|r| num(&r[rc])));
            for r in &csv.rows {
                let (x, y, v) = (num(&r[xc]), num(&r[yc]), num(&r[rc]));
                if !(x.is_finite() && y.is_finite() && v.is_finite()) {
                    continue;
                }
                let f = (v - cr.0) / (cr.1 - cr.0);
                let _ = writeln!(
                    s,
                    "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"3\" fill=\"rgb({},60,{})\"/>",
                    px(x),
                    py(y),
                    (255.0 * f) as u8,
                    (255.0 * (1.0 - f)) as u8
                );
            }
            continue;
        }
        let keys: Vec<Option<&String>> = if groups.is_empty() {
            vec![None]
        } else {
            groups.iter().map(Some).collect()
        };
        for (gi, key) in keys.iter().enumerate() {
            let mut pts: Vec<(f64, f64)> = csv
                .rows
                .iter()
                .filter(|r| key.is_none_or(|k| &r[group.expect("groups")] == k))
                .map(|r| (num(&r[xc]), num(&r[rc])))
                .filter(|(x, y)| x.is_finite() && y.is_finite())
                .collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            let colour = COLOURS[gi % COLOURS.len()];
            let path: Vec<String> = pts
                .iter()
                .map(|&(x, y)| format!("{:.1},{:.1}", px(x), py(y)))
                .collect();
            let _ = writeln!(
                s,
                "<polyline fill=\"none\" stroke=\"{colour}\" stroke-width=\"1.5\" points=\"{}\"/>",
                path.join(" ")
            );
            for &(x, y) in &pts {
                let _ = writeln!(
                    s,
                    "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"2.5\" fill=\"{colour}\"/>",
                    px(x),
                    py(y)
                );
            }
            if let (Some(k), Some(g), 0) = (key, group, i) {
                let _ = writeln!(
                    s,
                    "<text x=\"{:.1}\" y=\"{:.1}\" fill=\"{colour}\">{} = {}</text>",
                    x0 + 6.0,
                    y1 + 14.0 + 12.0 * gi as f64,
                    esc(&csv.header[g]),
                    esc(k)
                );
            }
        }
    }
    s.push_str("</svg>\n");
    Some(s)
}
