//! Start shapes of the sleeve (issue 11, item 2); the static solve of the kind then finds the
//! equilibrium. Nodes are placed at equal arc lengths.
//!
//! - Rolling lobe, between a top bead ring and a piston: a meridian from the bead `(r_b, h)`
//!   straight down to the outer side of a semicircular lobe, around it, and up along the piston
//!   contour to the clamp at the piston top. Its length is the sleeve length times a mean
//!   stretch.
//! - Convoluted, between a top and a bottom bead ring ([`convoluted_start`]): one half-ellipse
//!   lobe per convolution bulging away from the axis, through the girdle ring between two
//!   convolutions. A half ellipse on the chord between its ends leaves both ends perpendicular
//!   to the chord (along the plates for a vertical chord), so the start shape neither enters a
//!   plate nor overlaps the other lobe.

/// Points `[r, z]` of the start meridian, `n + 1` of them from the bead to the clamp, for a
/// piston contour `contour` (`[r, z]` from the base up, the last point its top edge = the
/// clamp), bead radius `r_b` [m] at height `h` [m], lobe outer radius `r_o` [m] and meridian
/// length `length` [m]. Errors when the length cannot form a lobe below the piston top.
pub fn rolling_lobe_start(
    contour: &[[f64; 2]],
    r_b: f64,
    h: f64,
    r_o: f64,
    length: f64,
    n: usize,
) -> Result<Vec<[f64; 2]>, String> {
    let top = *contour.last().ok_or("empty piston contour")?;
    let radius_at = |z: f64| -> f64 {
        if z <= contour[0][1] {
            return contour[0][0];
        }
        for w in contour.windows(2) {
            if z <= w[1][1] {
                let t = (z - w[0][1]) / (w[1][1] - w[0][1]);
                return w[0][0] + t * (w[1][0] - w[0][0]);
            }
        }
        top[0]
    };
    // the inner wall from height z up to the clamp along the contour
    let inner = |z: f64, out: Option<&mut Vec<[f64; 2]>>| -> f64 {
        let mut pts = vec![[radius_at(z), z]];
        for p in contour {
            if p[1] > z {
                pts.push(*p);
            }
        }
        let len = pts
            .windows(2)
            .map(|w| ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt())
            .sum();
        if let Some(o) = out {
            *o = pts;
        }
        len
    };
    let total = |zc: f64| -> f64 {
        let rp = radius_at(zc);
        let a = 0.5 * (r_o - rp);
        ((r_b - r_o).powi(2) + (h - zc).powi(2)).sqrt() + std::f64::consts::PI * a + inner(zc, None)
    };
    let z_hi = top[1].min(h);
    if total(z_hi) > length {
        return Err(format!(
            "the sleeve ({length:.4} m stretched) is too short to form a rolling lobe between the bead at height {h} m and the piston top at {} m",
            top[1]
        ));
    }
    // bisection on the lobe centre height
    let (mut lo, mut hi) = (z_hi - 10.0 * length, z_hi);
    if total(lo) < length {
        return Err("the sleeve is too long for its geometry".into());
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if total(mid) > length {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let zc = 0.5 * (lo + hi);
    let rp = radius_at(zc);
    let a = 0.5 * (r_o - rp);
    let rc = rp + a;
    let mut inner_pts = vec![];
    inner(zc, Some(&mut inner_pts));
    // sample the path at equal arc lengths
    let l_out = ((r_b - r_o).powi(2) + (h - zc).powi(2)).sqrt();
    let l_lobe = std::f64::consts::PI * a;
    let point = |s: f64| -> [f64; 2] {
        if s <= l_out {
            let t = s / l_out;
            return [r_b + t * (r_o - r_b), h + t * (zc - h)];
        }
        let s = s - l_out;
        if s <= l_lobe {
            let phi = s / a; // from the outer side (angle 0) down through the bottom
            return [rc + a * phi.cos(), zc - a * phi.sin()];
        }
        let mut s = s - l_lobe;
        for w in inner_pts.windows(2) {
            let l = ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt();
            if s <= l {
                let t = s / l;
                return [
                    w[0][0] + t * (w[1][0] - w[0][0]),
                    w[0][1] + t * (w[1][1] - w[0][1]),
                ];
            }
            s -= l;
        }
        top
    };
    let len = total(zc);
    let mut pts: Vec<[f64; 2]> = (0..=n).map(|k| point(len * k as f64 / n as f64)).collect();
    pts[0] = [r_b, h];
    pts[n] = top;
    Ok(pts)
}

/// `n + 1` points `[r, z]` at equal arc lengths on the half ellipse from `a` to `b` (the chord
/// one axis, the other semi-axis away from the axis of revolution) of arc length `length` [m].
/// Errors when `length` does not exceed the chord.
fn half_ellipse(a: [f64; 2], b: [f64; 2], length: f64, n: usize) -> Result<Vec<[f64; 2]>, String> {
    let (dr, dz) = (b[0] - a[0], b[1] - a[1]);
    let c = (dr * dr + dz * dz).sqrt();
    if length.is_nan() || length <= c * (1.0 + 1e-9) || c == 0.0 {
        return Err(format!(
            "a convolution of {length:.4} m (stretched sleeve) cannot span the {c:.4} m between its rings"
        ));
    }
    let u = [dr / c, dz / c];
    // the perpendicular pointing away from the axis
    let w = if -u[1] >= 0.0 {
        [-u[1], u[0]]
    } else {
        [u[1], -u[0]]
    };
    const DENSE: usize = 4000;
    let point = |e: f64, t: f64| -> [f64; 2] {
        let (x, y) = (-0.5 * c * t.cos(), e * t.sin());
        let m = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        [m[0] + x * u[0] + y * w[0], m[1] + x * u[1] + y * w[1]]
    };
    let arc = |e: f64, out: Option<&mut Vec<([f64; 2], f64)>>| -> f64 {
        let mut s = 0.0;
        let mut prev = point(e, 0.0);
        let mut pts = vec![(prev, 0.0)];
        for k in 1..=DENSE {
            let p = point(e, std::f64::consts::PI * k as f64 / DENSE as f64);
            s += ((p[0] - prev[0]).powi(2) + (p[1] - prev[1]).powi(2)).sqrt();
            pts.push((p, s));
            prev = p;
        }
        if let Some(o) = out {
            *o = pts;
        }
        s
    };
    let (mut lo, mut hi) = (0.0, length);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if arc(mid, None) < length {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let mut dense = vec![];
    let total = arc(0.5 * (lo + hi), Some(&mut dense));
    let mut out = Vec::with_capacity(n + 1);
    let mut j = 0;
    for k in 0..=n {
        let s = total * k as f64 / n as f64;
        while j + 1 < dense.len() - 1 && dense[j + 1].1 < s {
            j += 1;
        }
        let ((p0, s0), (p1, s1)) = (dense[j], dense[j + 1]);
        let t = ((s - s0) / (s1 - s0)).clamp(0.0, 1.0);
        out.push([p0[0] + t * (p1[0] - p0[0]), p0[1] + t * (p1[1] - p0[1])]);
    }
    out[0] = a;
    out[n] = b;
    Ok(out)
}

/// Points `[r, z]` of the start meridian of a convoluted sleeve, `n + 1` of them from the top
/// bead `top` to the bottom bead `bottom` (`[r, z]` [m]), of meridian length `length` [m]: one
/// half-ellipse lobe ([`half_ellipse`]), or with a girdle ring of radius `girdle` [m] two of
/// half the length each, through the girdle at mid-height (node `n / 2`; `n` even).
pub fn convoluted_start(
    top: [f64; 2],
    bottom: [f64; 2],
    girdle: Option<f64>,
    length: f64,
    n: usize,
) -> Result<Vec<[f64; 2]>, String> {
    match girdle {
        None => half_ellipse(top, bottom, length, n),
        Some(rg) => {
            if !n.is_multiple_of(2) || n < 2 {
                return Err(format!(
                    "{n} elements: a double-convoluted sleeve needs an even number (the girdle is the middle node)"
                ));
            }
            let mid = [rg, 0.5 * (top[1] + bottom[1])];
            let mut pts = half_ellipse(top, mid, 0.5 * length, n / 2)?;
            let lower = half_ellipse(mid, bottom, 0.5 * length, n / 2)?;
            pts.extend_from_slice(&lower[1..]);
            Ok(pts)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The convoluted start runs from bead to bead through the girdle at the middle node, with
    /// equal spacing and the asked length, bulging outwards but staying between the plates.
    #[test]
    fn convoluted_start_has_the_length_and_the_rings() {
        let pts = convoluted_start([0.115, 0.2], [0.115, 0.0], Some(0.11), 0.34, 40).unwrap();
        assert_eq!(pts.len(), 41);
        assert_eq!(pts[0], [0.115, 0.2]);
        assert_eq!(pts[20], [0.11, 0.1]);
        assert_eq!(pts[40], [0.115, 0.0]);
        let seg: Vec<f64> = pts
            .windows(2)
            .map(|w| ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt())
            .collect();
        let sum: f64 = seg.iter().sum();
        assert!((sum - 0.34).abs() < 1e-3, "{sum}");
        let (min, max) = seg
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &s| (a.min(s), b.max(s)));
        assert!(max - min < 1e-3 * max, "{min} {max}");
        assert!(pts.iter().all(|p| p[1] >= -1e-12 && p[1] <= 0.2 + 1e-12));
        let rmax = pts.iter().map(|p| p[0]).fold(0.0, f64::max);
        assert!(rmax > 0.15, "{rmax}");
        // a single convolution, and the errors
        let one = convoluted_start([0.12, 0.2], [0.1, 0.0], None, 0.3, 30).unwrap();
        assert_eq!((one[0], one[30]), ([0.12, 0.2], [0.1, 0.0]));
        assert!(convoluted_start([0.115, 0.2], [0.115, 0.0], Some(0.11), 0.34, 41).is_err());
        assert!(convoluted_start([0.115, 0.2], [0.115, 0.0], None, 0.19, 40).is_err());
    }

    /// The path runs from the bead to the clamp with equal spacing and has the asked length.
    #[test]
    fn start_meridian_has_the_length() {
        let contour = [[0.1, 0.0], [0.1, 0.15]];
        let pts = rolling_lobe_start(&contour, 0.14, 0.25, 0.148, 0.345, 60).unwrap();
        assert_eq!(pts.len(), 61);
        let seg: Vec<f64> = pts
            .windows(2)
            .map(|w| ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt())
            .collect();
        let sum: f64 = seg.iter().sum();
        // chords of the arc are slightly shorter than the arc
        assert!((sum - 0.345).abs() < 1e-3, "{sum}");
        assert_eq!(pts[0], [0.14, 0.25]);
        assert_eq!(pts[60], [0.1, 0.15]);
        // the lowest point is the lobe bottom, below the piston top
        let zmin = pts.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
        assert!(zmin < 0.1);
        assert!(rolling_lobe_start(&contour, 0.14, 0.25, 0.148, 0.1, 60).is_err());
    }
}
