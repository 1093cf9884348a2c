//! A [`Sketch`] as an SVG image (inline in the documentation page).

use super::xml_text::escape;
use crate::model::Sketch;

/// The drawing fitted into a `width` × `height` pixel box with a margin, with equal scales
/// on both axes (y up), plus a scale bar labelled in metres. `title` becomes the image's
/// `<title>`. An empty sketch gives a box with the words "no drawing".
pub fn sketch_svg(sketch: &Sketch, width: f64, height: f64, title: &str) -> String {
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" \
         viewBox=\"0 0 {width} {height}\"><title>{}</title>\
         <rect x=\"0\" y=\"0\" width=\"{width}\" height=\"{height}\" fill=\"#ffffff\" \
         stroke=\"#cccccc\"/>",
        escape(title)
    );
    let Some(fit) = Fit::new(sketch, width, height, 20.0) else {
        out.push_str(&format!(
            "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">no drawing</text></svg>",
            width / 2.0,
            height / 2.0
        ));
        return out;
    };
    for line in sketch.projected() {
        let pts: Vec<String> = line
            .iter()
            .map(|p| {
                let (x, y) = fit.pixel(*p);
                format!("{x:.2},{y:.2}")
            })
            .collect();
        out.push_str(&format!(
            "<polyline points=\"{}\" fill=\"none\" stroke=\"#1f4e9c\" stroke-width=\"1.5\" \
             stroke-linejoin=\"round\"/>",
            pts.join(" ")
        ));
    }
    // scale bar: the largest 1, 2 or 5 times a power of ten below a quarter of the width
    let bar = nice_length(0.25 * width / fit.scale);
    let px = bar * fit.scale;
    let y = height - 8.0;
    out.push_str(&format!(
        "<line x1=\"10\" y1=\"{y}\" x2=\"{:.2}\" y2=\"{y}\" stroke=\"#000000\" \
         stroke-width=\"2\"/><text x=\"{:.2}\" y=\"{:.2}\" font-size=\"11\">{} m</text></svg>",
        10.0 + px,
        14.0 + px,
        y + 4.0,
        format_length(bar)
    ));
    out
}

/// The largest of 1, 2, 5 times a power of ten not above `x` (> 0).
pub fn nice_length(x: f64) -> f64 {
    let p = 10f64.powf(x.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * p)
        .find(|&v| v <= x * (1.0 + 1e-12))
        .unwrap_or(p)
}

fn format_length(v: f64) -> String {
    let s = format!("{v:.6}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// Drawing coordinates [m] to pixels: equal scales, centred, y up.
pub(crate) struct Fit {
    /// Pixels per metre.
    pub scale: f64,
    cx: f64,
    cy: f64,
    w: f64,
    h: f64,
}

impl Fit {
    /// The fit of `sketch` into `w` × `h` pixels with `margin` pixels on every side; `None`
    /// when nothing is drawn. A drawing without extent (a point) gets 1 px per mm.
    pub fn new(sketch: &Sketch, w: f64, h: f64, margin: f64) -> Option<Self> {
        let lines = sketch.projected();
        let mut pts = lines.iter().flatten();
        let first = pts.next()?;
        let (mut lo, mut hi) = (*first, *first);
        for p in pts {
            lo = [lo[0].min(p[0]), lo[1].min(p[1])];
            hi = [hi[0].max(p[0]), hi[1].max(p[1])];
        }
        let (ex, ey) = (hi[0] - lo[0], hi[1] - lo[1]);
        let sx = if ex > 0.0 {
            (w - 2.0 * margin) / ex
        } else {
            f64::INFINITY
        };
        let sy = if ey > 0.0 {
            (h - 2.0 * margin) / ey
        } else {
            f64::INFINITY
        };
        let mut scale = sx.min(sy);
        if !scale.is_finite() {
            scale = 1000.0;
        }
        Some(Self {
            scale,
            cx: 0.5 * (lo[0] + hi[0]),
            cy: 0.5 * (lo[1] + hi[1]),
            w,
            h,
        })
    }

    /// Pixel position (x right, y down) of drawing point `p` [m].
    pub fn pixel(&self, p: [f64; 2]) -> (f64, f64) {
        (
            0.5 * self.w + self.scale * (p[0] - self.cx),
            0.5 * self.h - self.scale * (p[1] - self.cy),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_lengths() {
        assert_eq!(nice_length(0.37), 0.2);
        assert_eq!(nice_length(0.5), 0.5);
        assert_eq!(nice_length(7.0), 5.0);
        assert_eq!(nice_length(1.9e-3), 1e-3);
    }

    #[test]
    fn the_drawing_fills_the_box_with_equal_scales() {
        let mut s = Sketch::new("t");
        s.line_xy([[0.0, 0.0], [2.0, 1.0]]);
        let f = Fit::new(&s, 220.0, 220.0, 10.0).unwrap();
        assert_eq!(f.scale, 100.0);
        assert_eq!(f.pixel([0.0, 0.0]), (10.0, 160.0));
        assert_eq!(f.pixel([2.0, 1.0]), (210.0, 60.0));
        let svg = sketch_svg(&s, 220.0, 220.0, "a < b");
        assert!(svg.contains("<title>a &lt; b</title>"), "{svg}");
        assert!(svg.contains("points=\""), "{svg}");
    }

    #[test]
    fn an_empty_sketch_says_so() {
        let svg = sketch_svg(&Sketch::default(), 100.0, 80.0, "x");
        assert!(svg.contains("no drawing") && !svg.contains("polyline"));
    }
}
