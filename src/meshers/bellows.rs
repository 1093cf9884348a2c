//! The start shape of a rolling-lobe sleeve mounted between a top bead ring and a piston
//! (issue 11, item 2): a meridian from the bead `(r_b, h)` straight down to the outer side of
//! a semicircular lobe, around it, and up along the piston contour to the clamp at the piston
//! top. Its length is the sleeve length times a mean stretch; the static solve of the kind
//! then finds the equilibrium. Nodes are placed at equal arc lengths.

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

#[cfg(test)]
mod tests {
    use super::*;

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
