//! Gravity in the static pre-load of a belt drive (issue 12 item 5): a long slack horizontal
//! span sags as an elastic catenary.
//!
//! Reference (independent of the model): the elastic catenary of a cable of weight `w` per
//! unstretched length and axial stiffness EA (Irvine, *Cable Structures*, MIT Press 1981,
//! ch. 1, eqs. 1.20-1.21): with `s` the unstretched arc length from the lowest point, `H` the
//! horizontal tension, `V = w s`, `T = √(H² + V²)`,
//! `x(s) = H s/EA + (H/w) asinh(w s/H)`, `y(s) = w s²/(2 EA) + (H/w)(√(1 + (w s/H)²) − 1)`,
//! and along the cable `dT (1 + T/EA) = w dy`, i.e.
//! `T + T²/(2 EA) = H + H²/(2 EA) + w y` (for EA → ∞ the catenary's `T = H + w y`).

use flexfmu::elements::ancf_cable2d::{CableRule, CableSection};
use flexfmu::kinds::belt_drive::PulleySide;
use flexfmu::kinds::belt_drive::model::{
    BeltDrive, BeltElementKind, BeltPath, BeltSpec, PulleyDef, PulleyKind, default_contact,
};
use flexfmu::linalg::SolverKind;
use flexfmu::solver::newton::{NewtonPolicy, NewtonSettings};
use nalgebra::Vector2;

/// Coordinates per belt node (r, r').
const NC: usize = 4;

/// A two-pulley drive with a long horizontal span: centre distance 4 m, pulleys of 0.2 m,
/// a heavy soft belt (1 kg/m, EA 2e4 N: 1 % stretch at 200 N) at a low pre-tension (200 N),
/// EI 1e-3 N m² (bending length √(EI/T) = 2.2 mm against a 4 m span). Sag estimate
/// `w a²/(8 H)` = 9.81 · 16/1600 ≈ 0.1 m, 2.5 % of the span.
struct Slack {
    distance: f64,
    radius: f64,
    ea: f64,
    mass: f64,
    pretension: f64,
    n_el: usize,
    gravity: f64,
    mu: f64,
    load_steps: usize,
}

impl Slack {
    fn new() -> Self {
        Self {
            distance: 4.0,
            radius: 0.2,
            ea: 2e4,
            mass: 1.0,
            pretension: 200.0,
            n_el: 200,
            gravity: -9.81,
            mu: 0.4,
            load_steps: 1,
        }
    }

    fn model(&self) -> Result<BeltDrive, String> {
        let thickness = 0.004;
        let rp = self.radius + 0.5 * thickness;
        let newton = NewtonSettings {
            tolerance: 1e-8,
            max_iterations: 25,
            policy: NewtonPolicy::Full,
            line_search: true,
        };
        BeltDrive::new(BeltSpec {
            section: CableSection {
                ea: self.ea,
                ei: 1e-3,
                mass_per_length: self.mass,
                damping_axial: 5.0,
                damping_bending: 0.0,
                prestrain: 0.0,
            },
            element: BeltElementKind::Cable(CableRule::Full),
            thickness,
            pulleys: vec![
                PulleyDef {
                    center: Vector2::zeros(),
                    radius: self.radius,
                    kind: PulleyKind::Driven,
                    side: PulleySide::Front,
                },
                PulleyDef {
                    center: Vector2::new(self.distance, 0.0),
                    radius: self.radius,
                    kind: PulleyKind::Free {
                        inertia: 0.05,
                        damping: 0.1,
                    },
                    side: PulleySide::Front,
                },
            ],
            contact: default_contact(
                self.ea,
                self.mass,
                thickness,
                rp,
                rp,
                self.pretension,
                self.mu,
                (0.0, 0.0, 0.0),
            ),
            points_per_element: 4,
            gravity: Vector2::new(0.0, self.gravity),
            path: BeltPath::Closed {
                n_elements: self.n_el,
                pretension: self.pretension,
            },
            n_points: 0,
            track_energy: false,
            tensioner: None,
            statics: (newton, SolverKind::Auto, self.load_steps),
        })
    }
}

/// Elastic catenary from the lowest point at unstretched arc length `s` [m] (module doc):
/// `(x, y, T)` for horizontal tension `h` [N], weight `w` [N/m] per unstretched length, `ea` [N].
fn catenary(h: f64, w: f64, ea: f64, s: f64) -> (f64, f64, f64) {
    let u = w * s / h;
    (
        h * s / ea + h / w * u.asinh(),
        w * s * s / (2.0 * ea) + h / w * ((1.0 + u * u).sqrt() - 1.0),
        h * (1.0 + u * u).sqrt(),
    )
}

/// Unstretched arc length at which the catenary reaches `x` [m] (bisection: `x(s)` increases).
fn arc_at(h: f64, w: f64, ea: f64, x: f64) -> f64 {
    let (mut lo, mut hi) = (-100.0 * x.abs() - 1.0, 100.0 * x.abs() + 1.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if catenary(h, w, ea, mid).0 < x {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The lowest point of the lower span: material fraction, position [m] (golden-section search
/// of the interpolated centre line over the elements around the lowest node).
fn lowest_point(m: &BeltDrive, lower: &[usize]) -> Vector2<f64> {
    let n = m.n_elements() as f64;
    let k = *lower
        .iter()
        .min_by(|a, b| node(m, **a).0.y.total_cmp(&node(m, **b).0.y))
        .unwrap();
    let (mut a, mut b) = ((k as f64 - 1.0) / n, (k as f64 + 1.0) / n);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..80 {
        let (c, d) = (b - g * (b - a), a + g * (b - a));
        if m.belt_point(c).y < m.belt_point(d).y {
            b = d;
        } else {
            a = c;
        }
    }
    m.belt_point(0.5 * (a + b))
}

/// Element `e`'s axial force at its middle times the cosine of its chord's slope: the
/// horizontal tension [N].
fn horizontal_tension(m: &BeltDrive, e: usize) -> f64 {
    let (a, b) = (node(m, e).0, node(m, (e + 1) % m.n_elements()).0);
    let d = b - a;
    m.element_tension(e) * d.x.abs() / d.norm()
}

/// What the catenary check measured.
struct Sag {
    /// Horizontal tension at the lowest point [N].
    h: f64,
    /// Lowest point, model [m].
    low: Vector2<f64>,
    /// Lowest point predicted by the catenary of tension `h` tangent to both pitch circles.
    low_ref: Vector2<f64>,
    /// Sag below the tangent points, catenary [m].
    sag_ref: f64,
    /// Span between the tangent points [m].
    span: f64,
    /// Largest |y − y_catenary| over the free span's nodes [m].
    shape_err: f64,
    /// Largest |T − T_catenary(y)| over the free span's elements [N].
    tension_err: f64,
    /// Tension rise w·sag from the lowest point to the tangent points, catenary [N].
    rise_ref: f64,
    /// Largest tension rise over the free span's elements, model and catenary [N].
    rise: (f64, f64),
}

/// The catenary check of the lower span of `d`'s pre-loaded model `m`.
fn check_lower_span(d: &Slack, m: &BeltDrive) -> Sag {
    let w = d.mass * d.gravity.abs();
    let ea = d.ea;
    let law = m.contact_law();
    let rho = d.radius + 0.002;
    let n = m.n_elements();
    // nodes of the lower span clear of the pulleys (5 mm above contact)
    // nodes of the lower span 0.2 m (4 elements of the 200) or more from the pulleys'
    // bottoms: the tension settles within about 3 elements of the contact entry (element
    // length 46 mm against the bending length √(EI/T) = 2.2 mm)
    let clear = |r: Vector2<f64>| r.y < 0.0 && r.x > 0.2 && r.x < d.distance - 0.2;
    let lower: Vec<usize> = (0..n).filter(|&k| clear(node(m, k).0)).collect();
    let low = lowest_point(m, &lower);
    let e_low = *lower
        .iter()
        .min_by(|a, b| {
            (node(m, **a).0.x - low.x)
                .abs()
                .total_cmp(&(node(m, **b).0.x - low.x).abs())
        })
        .unwrap();
    let e_low = if node(m, e_low).0.x > low.x {
        (e_low + n - 1) % n
    } else {
        e_low
    };
    let h = horizontal_tension(m, e_low);
    // tangency to both pitch circles (radius less the contact penetration T/(ρ k_n) + δ0/2):
    // by symmetry at arc lengths ±s*, x(s*) − ρ' V/T = D/2
    let radius = |t: f64| rho - t / (rho * law.k_n) - 0.5 * law.smoothing;
    let reach = |s: f64| {
        let (x, _, t) = catenary(h, w, ea, s);
        x - radius(t) * w * s / t
    };
    let (mut lo, mut hi) = (0.0, d.distance);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if reach(mid) < 0.5 * d.distance {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let s_t = 0.5 * (lo + hi);
    let (x_t, sag_ref, t_t) = catenary(h, w, ea, s_t);
    let low_ref = Vector2::new(0.5 * d.distance, -radius(t_t) * h / t_t - sag_ref);
    let shape_err = lower
        .iter()
        .map(|&k| {
            let r = node(m, k).0;
            let (_, y, _) = catenary(h, w, ea, arc_at(h, w, ea, r.x - low.x));
            (r.y - low.y - y).abs()
        })
        .fold(0.0, f64::max);
    // along the span: T + T²/(2 EA) = H + H²/(2 EA) + w (y − y_low), at element middles
    let energy = |t: f64| t + t * t / (2.0 * ea);
    let (mut tension_err, mut rise) = (0.0f64, (0.0f64, 0.0f64));
    for &e in &lower {
        if !lower.contains(&((e + 1) % n)) {
            continue;
        }
        let y = m.belt_point((e as f64 + 0.5) / n as f64).y;
        let target = energy(h) + w * (y - low.y);
        let t_ref = (-1.0 + (1.0 + 2.0 * target / ea).sqrt()) * ea;
        let t = m.element_tension(e);
        tension_err = tension_err.max((t - t_ref).abs());
        if t_ref - h > rise.1 {
            rise = (t - h, t_ref - h);
        }
    }
    Sag {
        h,
        low,
        low_ref,
        sag_ref,
        span: 2.0 * x_t,
        shape_err,
        tension_err,
        rise_ref: t_t - h,
        rise,
    }
}

/// Node `k`: position and slope vector r'.
fn node(m: &BeltDrive, k: usize) -> (Vector2<f64>, Vector2<f64>) {
    let q = m.coordinates();
    (
        Vector2::new(q[k * NC], q[k * NC + 1]),
        Vector2::new(q[k * NC + 2], q[k * NC + 3]),
    )
}

/// The lower span of the pre-loaded slack drive against the elastic catenary whose horizontal
/// tension H is the model's at the lowest point (element force times the cosine of its slope):
/// * sag: the catenary of tension H tangent to both pitch circles (radius less the contact
///   penetration) puts the lowest point at `y_ref`; the model's lowest point within 0.3 % of
///   the sag (measured 0.05 %). The inextensible catenary `H/w (cosh(w a/2H) − 1)` over the
///   span `a` between the tangent points is 1.0 % deeper here (the belt stretches 1 %), so
///   the tolerance tells the elastic catenary from the inextensible one; what it allows is
///   the contact entry, resolved by 46 mm elements against a 2.2 mm bending length;
/// * shape: the nodes 0.2 m and more from the tangent points on the catenary through the
///   lowest point within 1e-3 of the sag (measured 6e-8);
/// * tension along the span: `T + T²/(2 EA) = H + H²/(2 EA) + w (y − y_low)` at the element
///   middles there within 1 % of the tension rise w·(y − y_low) (measured 0.03 %; the
///   elements within 3 of the contact entry are off by up to 0.3 N of 200 N).
#[test]
fn sagging_span_is_an_elastic_catenary() {
    let d = Slack::new();
    let m = d.model().unwrap();
    let s = check_lower_span(&d, &m);
    let w = d.mass * d.gravity.abs();
    let inextensible = s.h / w * ((w * s.span / (2.0 * s.h)).cosh() - 1.0);
    println!(
        "slack drive, 200 elements: H = {:.3} N, span between tangent points a = {:.4} m",
        s.h, s.span
    );
    println!("| quantity | model | elastic catenary |");
    println!("|---|---|---|");
    println!(
        "| lowest point x, y [m] | {:.6}, {:.6} | {:.6}, {:.6} |",
        s.low.x, s.low.y, s.low_ref.x, s.low_ref.y
    );
    println!(
        "| sag below the tangent points [m] | {:.6} | {:.6} (inextensible H/w (cosh(wa/2H) - 1): {inextensible:.6}) |",
        s.sag_ref + (s.low_ref.y - s.low.y),
        s.sag_ref
    );
    println!(
        "| shape, largest |y - y_cat| [m] | {:.2e} | 0 |",
        s.shape_err
    );
    println!(
        "| tension rise to the last clear element [N] | {:.4} | {:.4} (largest error {:.2e} N) |",
        s.rise.0, s.rise.1, s.tension_err
    );
    println!(
        "| tension rise to the tangent points w * sag (elastic) [N] | - | {:.4} |",
        s.rise_ref
    );
    let sag_err = (s.low.y - s.low_ref.y).abs() / s.sag_ref;
    assert!(
        s.sag_ref > 0.02 * s.span,
        "the sag should be a few % of the span: {} of {}",
        s.sag_ref,
        s.span
    );
    assert!(
        sag_err < 3e-3,
        "lowest point off by {sag_err:.2e} of the sag"
    );
    assert!(
        (inextensible - s.sag_ref).abs() > 3.0 * 3e-3 * s.sag_ref,
        "the check should tell the elastic from the inextensible catenary"
    );
    assert!(
        (s.low.x - s.low_ref.x).abs() < 1e-3,
        "lowest point at x = {}",
        s.low.x
    );
    assert!(
        s.shape_err < 1e-3 * s.sag_ref,
        "shape error {}",
        s.shape_err
    );
    assert!(s.rise.1 > 0.5, "tension rise {}", s.rise.1);
    assert!(
        s.tension_err < 0.01 * s.rise.1,
        "tension along the span off by {} N",
        s.tension_err
    );
}

/// `belt.pretension` with gravity is the mean over the spans of the axial force at the span
/// middles (what `belt.tension_tight`/`slack` and `spanN.tension` report at rest): the
/// pre-load reaches it within its 0.1 % tolerance, and on a horizontal span that force is the
/// catenary's horizontal tension H at the lowest point (0.05 %). The reference-length
/// correction knows that the sag takes up length (`sag_coeff`, `preload.rs`): at most 3
/// static solves on the base drive, the stiffer belt (EA 1e5 N), the heavier one (2 kg/m) and
/// the slacker one (100 N) (the elastic correction alone took 5 solves, the round limit, on
/// the base drive; a secant on the mean tension 3, 5 and 5 on the first three). Without
/// gravity the same drive's spans are straight.
#[test]
fn pretension_is_the_mean_mid_span_tension() {
    for d in [
        Slack::new(),
        Slack {
            ea: 1e5,
            ..Slack::new()
        },
        Slack {
            mass: 2.0,
            ..Slack::new()
        },
        Slack {
            pretension: 100.0,
            ..Slack::new()
        },
    ] {
        let m = d.model().unwrap();
        let spans = m.span_tensions();
        let mean = spans.iter().sum::<f64>() / spans.len() as f64;
        let s = check_lower_span(&d, &m);
        let rep = m.preload_report();
        println!(
            "EA {} N, {} kg/m, pretension {} N: span tensions {:.3?} N (mean {mean:.3}), H lower span {:.3} N, sag {:.4} m, {} solves, {} Newton iterations",
            d.ea, d.mass, d.pretension, spans, s.h, s.sag_ref, rep.solves, rep.iterations
        );
        assert!(
            (mean - d.pretension).abs() <= 1e-3 * d.pretension,
            "mean {mean}"
        );
        assert!(
            (spans[0] - s.h).abs() < 5e-4 * s.h,
            "{} vs H {}",
            spans[0],
            s.h
        );
        assert!(rep.solves <= 3, "{} solves", rep.solves);
    }
    let d = Slack {
        gravity: 0.0,
        ..Slack::new()
    };
    let m = d.model().unwrap();
    let lowest = (0..m.n_elements())
        .map(|k| node(&m, k).0.y)
        .fold(f64::INFINITY, f64::min);
    let spans = m.span_tensions();
    println!("without gravity: lowest node y = {lowest:.6} m, span tensions {spans:.3?} N");
    assert!(lowest > -(d.radius + 0.002) - 1e-4, "lowest node {lowest}");
    assert!((spans[0] - d.pretension).abs() <= 1e-3 * d.pretension);
}

/// The static solver's load stepping (`solver.load_steps` = 4: gravity applied in four
/// increments with the tangent predictor) reaches the same pre-load as one step.
#[test]
fn load_stepping_reaches_the_same_preload() {
    let one = Slack::new().model().unwrap();
    let four = Slack {
        load_steps: 4,
        ..Slack::new()
    }
    .model()
    .unwrap();
    let diff = one
        .coordinates()
        .iter()
        .zip(four.coordinates())
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!("load steps 1 and 4: largest coordinate difference {diff:.2e}");
    assert!(diff < 1e-7, "{diff}");
}

/// The serpentine drive (`scenes/serpentine.toml`, tensioner) with `gravity.y` = −9.81 m/s²:
/// the frictionless pre-load with the belt anchored by a spring converges (sliding round the
/// loop does not change the weight's potential, so the anchor carries no gravity load), and the
/// short, taut spans (0.1 kg/m at 350 N) barely move the arm (measured 0.04 mrad, spans within
/// 0.25 N).
#[test]
fn serpentine_preload_converges_with_gravity() {
    use flexfmu::scene::{ParamValues, Scene};
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/serpentine.toml"
    ))
    .unwrap();
    let build = |text: &str| {
        let scene = Scene::from_toml(text).unwrap();
        let p = ParamValues::defaults(&scene.params);
        BeltDrive::build(scene.tables().unwrap(), &p).unwrap()
    };
    // the Lagrangian drive's pre-load (the shipped scene is an ALE belt, mounted on it)
    let text = text.replace("formulation = \"ale\"", "formulation = \"lagrangian\"");
    let flat = build(&text);
    let heavy = build(&format!("{text}\n[gravity]\ny = -9.81\n"));
    let angle = |m: &BeltDrive| {
        use flexfmu::kinds::belt_drive::scene::{BeltOutput, Output};
        m.output_of(Output::Belt(BeltOutput::TensionerAngle))
    };
    println!(
        "serpentine: arm angle {:.4} mrad without, {:.4} mrad with gravity; spans {:.2?} / {:.2?} N; frictionless {} / {}",
        1e3 * angle(&flat),
        1e3 * angle(&heavy),
        flat.span_tensions(),
        heavy.span_tensions(),
        flat.preload_was_frictionless(),
        heavy.preload_was_frictionless()
    );
    assert!(heavy.preload_was_frictionless());
    // against the arm's travel of about 50 mrad in the tensioner statics test
    assert!((angle(&heavy) - angle(&flat)).abs() < 1e-4);
    for (a, b) in flat.span_tensions().iter().zip(heavy.span_tensions()) {
        assert!(
            (a - b).abs() < 1.0,
            "span tension {a} N without, {b} N with gravity"
        );
    }
}
