//! Analytic and published reference solutions for the shell validation tests (issue 10).
//!
//! Every function is pure (no state, no allocation that outlives the call) and names its source.
//! Units are SI throughout unless a function says it is dimensionless: lengths in m, forces in N,
//! pressures in Pa, moments in N m, bending stiffness `D` and `EI` in N m (plate, per unit width)
//! and N m² (beam), density in kg/m³, angular frequencies in rad/s.
//!
//! Contents:
//! - simply supported rectangular Kirchhoff plate: Navier series for uniform pressure and for a
//!   point load, Lévy single-series centre values (independent checks), natural frequencies;
//! - clamped circular plate: deflection under uniform pressure and under a central point load,
//!   the fundamental frequency from its Bessel-function frequency equation;
//! - closed thin cylinder under internal pressure (membrane solution away from the end caps);
//! - cantilever strip rolled up by an end moment (exact circular arc);
//! - cantilever under a tip shear force (inextensible elastica): elliptic-integral closed form and
//!   an independent RK4 shooting solution.

use std::f64::consts::{FRAC_1_SQRT_2, PI};

// ---------------------------------------------------------------------------------------------
// Simply supported rectangular plate
// ---------------------------------------------------------------------------------------------

/// Flexural rigidity of a plate, `D = E h³ / (12 (1 − ν²))` [N m].
///
/// Timoshenko & Woinowsky-Krieger, *Theory of Plates and Shells*, 2nd ed. (1959), eq. (3).
/// `e` Young's modulus [Pa], `h` thickness [m], `nu` Poisson's ratio [-].
pub fn plate_rigidity(e: f64, h: f64, nu: f64) -> f64 {
    e * h * h * h / (12.0 * (1.0 - nu * nu))
}

/// Largest (odd) index `m`, `n` kept by [`navier_uniform_deflection`]: 801, i.e. 401 odd terms per
/// direction, 160 801 terms in all. The truncation error of the double series decays as `N⁻⁴`;
/// with this `N` it is below 1e-10 relative at the centre and below 1e-8 relative at every
/// interior point at least 2 % of the span from an edge (checked in `tests/shell_reference.rs`
/// against the series with twice as many terms and against the Lévy single series).
pub const NAVIER_UNIFORM_MAX_INDEX: usize = 801;

/// Deflection `w(x, y)` [m] of a simply supported rectangular plate `0 ≤ x ≤ a`, `0 ≤ y ≤ b`
/// under a uniform pressure `q` [Pa] (positive along `w`), Navier double series
///
/// `w = 16 q / (π⁶ D) Σ_{m,n odd} sin(mπx/a) sin(nπy/b) / (m n (m²/a² + n²/b²)²)`
///
/// (Timoshenko & Woinowsky-Krieger, *Theory of Plates and Shells*, 2nd ed., §28, Navier solution), summed over
/// odd `m, n ≤` [`NAVIER_UNIFORM_MAX_INDEX`]. `d` is the flexural rigidity [N m].
pub fn navier_uniform_deflection(a: f64, b: f64, d: f64, q: f64, x: f64, y: f64) -> f64 {
    navier_uniform_deflection_n(a, b, d, q, x, y, NAVIER_UNIFORM_MAX_INDEX)
}

/// [`navier_uniform_deflection`] truncated at odd indices `m, n ≤ max_index` [m].
pub fn navier_uniform_deflection_n(
    a: f64,
    b: f64,
    d: f64,
    q: f64,
    x: f64,
    y: f64,
    max_index: usize,
) -> f64 {
    let odd: Vec<f64> = (1..=max_index).step_by(2).map(|i| i as f64).collect();
    let sx: Vec<f64> = odd.iter().map(|&m| (m * PI * x / a).sin()).collect();
    let sy: Vec<f64> = odd.iter().map(|&n| (n * PI * y / b).sin()).collect();
    let mut sum = 0.0;
    // Sum the smallest terms first (large m, n) to keep the rounding error low.
    for (i, &m) in odd.iter().enumerate().rev() {
        let mut row = 0.0;
        for (j, &n) in odd.iter().enumerate().rev() {
            let k = m * m / (a * a) + n * n / (b * b);
            row += sy[j] / (n * k * k);
        }
        sum += sx[i] * row / m;
    }
    16.0 * q / (PI.powi(6) * d) * sum
}

/// Centre deflection [m] of a simply supported rectangular plate under uniform pressure `q` [Pa]
/// from the Lévy single series (Timoshenko & Woinowsky-Krieger, §30, the deflection at `y = 0`):
///
/// `w_max = 4 q a⁴ / (π⁵ D) Σ_{m odd} (−1)^((m−1)/2) / m⁵ · (1 − (α_m tanh α_m + 2) / (2 cosh α_m))`,
/// `α_m = m π b / (2a)`.
///
/// An independent check of [`navier_uniform_deflection`]; 2000 odd terms (error below 1e-16).
pub fn levy_uniform_centre_deflection(a: f64, b: f64, d: f64, q: f64) -> f64 {
    let mut sum = 0.0;
    for i in (0..2000).rev() {
        let m = (2 * i + 1) as f64;
        let alpha = m * PI * b / (2.0 * a);
        let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
        // (α tanh α + 2) / (2 cosh α) without overflow for large α.
        let frac = if alpha > 350.0 {
            0.0
        } else {
            (alpha * alpha.tanh() + 2.0) / (2.0 * alpha.cosh())
        };
        sum += sign / m.powi(5) * (1.0 - frac);
    }
    4.0 * q * a.powi(4) / (PI.powi(5) * d) * sum
}

/// Number of terms `m = 1 ..= NAVIER_POINT_TERMS` of the outer sum in
/// [`navier_point_deflection`]. Under the load the terms decay as `m⁻³`, so the truncation error
/// decays as `M⁻²`: with 40 000 terms it is below 1e-9 relative at the load point of a square
/// plate (checked against the Lévy centre series), and far smaller elsewhere.
pub const NAVIER_POINT_TERMS: usize = 40_000;

/// Deflection `w(x, y)` [m] of a simply supported rectangular plate `0 ≤ x ≤ a`, `0 ≤ y ≤ b`
/// under a point load `p` [N] at `(xi, eta)`, Navier double series
///
/// `w = 4 P / (π⁴ a b D) Σ_{m,n ≥ 1} sin(mπξ/a) sin(nπη/b) sin(mπx/a) sin(nπy/b) / (m²/a² + n²/b²)²`
///
/// (Timoshenko & Woinowsky-Krieger, ch. 5, concentrated load on a simply supported plate). The inner sum over `n` is summed exactly in
/// closed form (from `Σ cos nθ / (n² + c²) = π cosh(c(π − θ)) / (2c sinh cπ) − 1/(2c²)`,
/// Gradshteyn & Ryzhik 1.445.2, differentiated with respect to `c²`); the outer sum over `m` is
/// truncated at [`NAVIER_POINT_TERMS`]. The plain double series converges only as `N⁻²` under the
/// load, which would need some 10⁸ terms for 1e-8; [`navier_point_deflection_double`] is that
/// plain series, used to check this one.
#[allow(clippy::too_many_arguments)]
pub fn navier_point_deflection(
    a: f64,
    b: f64,
    d: f64,
    p: f64,
    xi: f64,
    eta: f64,
    x: f64,
    y: f64,
) -> f64 {
    navier_point_deflection_m(a, b, d, p, xi, eta, x, y, NAVIER_POINT_TERMS)
}

/// [`navier_point_deflection`] with the outer sum truncated at `m ≤ terms` [m].
#[allow(clippy::too_many_arguments)]
pub fn navier_point_deflection_m(
    a: f64,
    b: f64,
    d: f64,
    p: f64,
    xi: f64,
    eta: f64,
    x: f64,
    y: f64,
    terms: usize,
) -> f64 {
    let theta1 = PI * (y - eta).abs() / b;
    let theta2 = PI * (y + eta) / b;
    let mut sum = 0.0;
    for m in (1..=terms).rev() {
        let mf = m as f64;
        let c = mf * b / a;
        let inner = 0.5 * (inner_cos_sum(c, theta1) - inner_cos_sum(c, theta2));
        sum += (mf * PI * xi / a).sin() * (mf * PI * x / a).sin() * inner;
    }
    4.0 * p * b.powi(4) / (PI.powi(4) * a * b * d) * sum
}

/// `Σ_{n ≥ 1} cos(nθ) / (n² + c²)²` for `0 ≤ θ ≤ 2π`, up to the term `−1/(2c⁴)` that is the same
/// for every `θ` (it cancels in the differences [`navier_point_deflection_m`] takes).
fn inner_cos_sum(c: f64, theta: f64) -> f64 {
    // R = cosh(c(π−θ))/sinh(cπ), S = sinh(c(π−θ))/sinh(cπ), coth(cπ), written with decaying
    // exponentials so that large c does not overflow.
    let e0 = (-c * theta).exp();
    let e1 = (-c * (2.0 * PI - theta)).exp();
    let e2 = (-2.0 * PI * c).exp();
    let r = (e0 + e1) / (1.0 - e2);
    let s = (e0 - e1) / (1.0 - e2);
    let coth = (1.0 + e2) / (1.0 - e2);
    let dr_dc = (PI - theta) * s - PI * r * coth;
    PI * r / (4.0 * c * c * c) - PI / (4.0 * c * c) * dr_dc
}

/// The plain Navier double series of [`navier_point_deflection`], truncated at `m, n ≤ max_index`
/// [m]. Slow to converge under the load (error `∝ N⁻²`); for checks only.
#[allow(clippy::too_many_arguments)]
pub fn navier_point_deflection_double(
    a: f64,
    b: f64,
    d: f64,
    p: f64,
    xi: f64,
    eta: f64,
    x: f64,
    y: f64,
    max_index: usize,
) -> f64 {
    let fx: Vec<f64> = (1..=max_index)
        .map(|m| (m as f64 * PI * xi / a).sin() * (m as f64 * PI * x / a).sin())
        .collect();
    let fy: Vec<f64> = (1..=max_index)
        .map(|n| (n as f64 * PI * eta / b).sin() * (n as f64 * PI * y / b).sin())
        .collect();
    let mut sum = 0.0;
    for m in (1..=max_index).rev() {
        let mut row = 0.0;
        for n in (1..=max_index).rev() {
            let k = (m * m) as f64 / (a * a) + (n * n) as f64 / (b * b);
            row += fy[n - 1] / (k * k);
        }
        sum += fx[m - 1] * row;
    }
    4.0 * p / (PI.powi(4) * a * b * d) * sum
}

/// Centre deflection [m] of a simply supported rectangular plate under a central point load `p`
/// [N], Lévy single series (Timoshenko & Woinowsky-Krieger, ch. 5, the maximum deflection under a
/// central concentrated load):
///
/// `w_max = P a² / (2 π³ D) Σ_{m odd} (tanh α_m − α_m / cosh² α_m) / m³`, `α_m = m π b / (2a)`.
///
/// The terms decay as `m⁻³`: 200 000 odd terms leave a truncation error of about 2e-12 relative.
/// An independent check of [`navier_point_deflection`].
pub fn levy_point_centre_deflection(a: f64, b: f64, d: f64, p: f64) -> f64 {
    let mut sum = 0.0;
    for i in (0..200_000).rev() {
        let m = (2 * i + 1) as f64;
        let alpha = m * PI * b / (2.0 * a);
        let sech2 = if alpha > 350.0 {
            0.0
        } else {
            1.0 / (alpha.cosh() * alpha.cosh())
        };
        sum += (alpha.tanh() - alpha * sech2) / (m * m * m);
    }
    p * a * a / (2.0 * PI.powi(3) * d) * sum
}

/// Natural angular frequency `ω_mn = π² (m²/a² + n²/b²) √(D / (ρ h))` [rad/s] of the simply
/// supported rectangular plate `a × b` [m] (`m`, `n` half-waves along `x`, `y`), `d` flexural
/// rigidity [N m], `rho` density [kg/m³], `h` thickness [m].
///
/// Leissa, *Vibration of Plates*, NASA SP-160 (1969), chapter 4 (the SS-SS-SS-SS plate, whose
/// modes are `sin(mπx/a) sin(nπy/b)`).
pub fn ss_plate_frequency(a: f64, b: f64, d: f64, rho: f64, h: f64, m: u32, n: u32) -> f64 {
    let (m, n) = (m as f64, n as f64);
    PI * PI * (m * m / (a * a) + n * n / (b * b)) * (d / (rho * h)).sqrt()
}

// ---------------------------------------------------------------------------------------------
// Clamped circular plate
// ---------------------------------------------------------------------------------------------

/// Deflection `w(r)` [m] of a clamped circular plate of radius `a` [m] under uniform pressure `q`
/// [Pa]: `w = q (a² − r²)² / (64 D)`, centre `q a⁴ / (64 D)`.
///
/// Timoshenko & Woinowsky-Krieger, *Theory of Plates and Shells*, §15 (uniformly loaded circular
/// plates, clamped edge).
pub fn clamped_circular_uniform_deflection(a: f64, d: f64, q: f64, r: f64) -> f64 {
    let s = a * a - r * r;
    q * s * s / (64.0 * d)
}

/// Deflection `w(r)` [m] of a clamped circular plate of radius `a` [m] under a central point load
/// `p` [N]: `w = P / (16 π D) (2 r² ln(r/a) + a² − r²)`, centre `P a² / (16 π D)`.
///
/// Timoshenko & Woinowsky-Krieger, *Theory of Plates and Shells*, §19 (circular plate loaded at
/// the centre, clamped edge).
pub fn clamped_circular_point_deflection(a: f64, d: f64, p: f64, r: f64) -> f64 {
    let log_term = if r > 0.0 {
        2.0 * r * r * (r / a).ln()
    } else {
        0.0
    };
    p / (16.0 * PI * d) * (log_term + a * a - r * r)
}

/// Frequency parameter `λ² = ω a² √(ρ h / D)` [-] of the fundamental (axisymmetric, no nodal
/// circle) mode of a clamped circular plate: the first root `λ` of the frequency equation
/// `J₀(λ) I₁(λ) + I₀(λ) J₁(λ) = 0` (Leissa, *Vibration of Plates*, NASA SP-160, §2.1.1, the
/// frequency equation `J_n(λ) I_n'(λ) − I_n(λ) J_n'(λ) = 0` with n = 0), squared. Computed here from the power series of the Bessel functions and bisection;
/// Leissa's Table 2.1 gives 10.2158.
pub fn clamped_circular_lambda2() -> f64 {
    let f = |l: f64| bessel_j(0, l) * bessel_i(1, l) + bessel_i(0, l) * bessel_j(1, l);
    let (mut lo, mut hi) = (2.5, 4.0);
    assert!(f(lo) * f(hi) < 0.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(lo) * f(mid) <= 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let l = 0.5 * (lo + hi);
    l * l
}

/// Fundamental angular frequency `ω = λ² / a² √(D / (ρ h))` [rad/s] of a clamped circular plate
/// of radius `a` [m] (Leissa, NASA SP-160, §2.1.1; `λ²` from [`clamped_circular_lambda2`]).
pub fn clamped_circular_frequency(a: f64, d: f64, rho: f64, h: f64) -> f64 {
    clamped_circular_lambda2() / (a * a) * (d / (rho * h)).sqrt()
}

/// Bessel function of the first kind `J_n(x)` [-] by its power series (adequate for `|x| < 10`).
fn bessel_j(n: u32, x: f64) -> f64 {
    bessel_series(n, x, -1.0)
}

/// Modified Bessel function `I_n(x)` [-] by its power series (adequate for `|x| < 10`).
fn bessel_i(n: u32, x: f64) -> f64 {
    bessel_series(n, x, 1.0)
}

/// `Σ_k s^k (x/2)^(2k+n) / (k! (k+n)!)`, `s = −1` for `J_n`, `+1` for `I_n`.
fn bessel_series(n: u32, x: f64, s: f64) -> f64 {
    let half = 0.5 * x;
    let mut term = half.powi(n as i32) / (1..=n).map(f64::from).product::<f64>();
    let mut sum = term;
    for k in 1..60 {
        term *= s * half * half / (k as f64 * (k + n) as f64);
        sum += term;
    }
    sum
}

// ---------------------------------------------------------------------------------------------
// Closed thin cylinder under internal pressure
// ---------------------------------------------------------------------------------------------

/// A closed thin-walled circular cylinder (membrane state far from the end caps).
///
/// Membrane stresses `σ_θ = p R / t`, `σ_x = p R / (2 t)` and plane-stress Hooke's law: Timoshenko,
/// *Strength of Materials* Part II, §53 (thin-walled cylinder), and Roark's *Formulas for Stress
/// and Strain*, 7th ed., Table 13.1 case 1c (`ΔR = q R² (1 − ν/2) / (E t)`,
/// `ΔL = q R L (1 − 2ν) / (2 E t)`). All results are first order in `p`.
#[derive(Clone, Copy, Debug)]
pub struct ClosedCylinder {
    /// Mid-surface radius R [m].
    pub radius: f64,
    /// Wall thickness t [m].
    pub thickness: f64,
    /// Length L of the cylindrical part [m].
    pub length: f64,
    /// Young's modulus E [Pa].
    pub e: f64,
    /// Poisson's ratio ν [-].
    pub nu: f64,
}

impl ClosedCylinder {
    /// Hoop strain `ε_θ = p R / (E t) (1 − ν/2)` [-] under internal pressure `p` [Pa].
    pub fn hoop_strain(&self, p: f64) -> f64 {
        p * self.radius / (self.e * self.thickness) * (1.0 - 0.5 * self.nu)
    }

    /// Axial strain `ε_x = p R / (2 E t) (1 − 2ν)` [-] under internal pressure `p` [Pa].
    pub fn axial_strain(&self, p: f64) -> f64 {
        p * self.radius / (2.0 * self.e * self.thickness) * (1.0 - 2.0 * self.nu)
    }

    /// Change of the mid-surface radius `ΔR = R ε_θ` [m].
    pub fn radius_change(&self, p: f64) -> f64 {
        self.radius * self.hoop_strain(p)
    }

    /// Change of the length of the cylindrical part `ΔL = L ε_x` [m].
    pub fn length_change(&self, p: f64) -> f64 {
        self.length * self.axial_strain(p)
    }

    /// Volume `π R² L` enclosed by the cylindrical part (mid-surface) [m³].
    pub fn volume(&self) -> f64 {
        PI * self.radius * self.radius * self.length
    }

    /// Change of the volume of the cylindrical part to first order,
    /// `ΔV = V (2 ε_θ + ε_x) = V p R (5 − 4ν) / (2 E t)` [m³].
    pub fn volume_change(&self, p: f64) -> f64 {
        self.volume() * (2.0 * self.hoop_strain(p) + self.axial_strain(p))
    }
}

// ---------------------------------------------------------------------------------------------
// Cantilever strip rolled up by an end moment
// ---------------------------------------------------------------------------------------------

/// End moment `M = 2π EI / L` [N m] that rolls a cantilever of length `l` [m] and bending
/// stiffness `ei` [N m²] into a full ring (tip back at the root).
pub fn rollup_full_ring_moment(l: f64, ei: f64) -> f64 {
    2.0 * PI * ei / l
}

/// Tip position `(x, z)` [m] of an inextensible cantilever of length `l` [m], bending stiffness
/// `ei` [N m²], clamped at the origin along `+x`, under an end moment `m` [N m] about `−y` that
/// bends it towards `+z`.
///
/// The moment is constant along the beam, so the exact deformed shape is a circular arc of radius
/// `ρ = EI / M` through the angle `θ = M L / EI`: `x = ρ sin θ`, `z = ρ (1 − cos θ)` (Euler's
/// elastica with a pure end moment; the roll-up benchmark of Sze, Liu & Lo 2004, Finite Elem.
/// Anal. Des. 40:1551–1569, §3.2). Written as `L sin θ / θ`, `L · 2 sin²(θ/2) / θ` so that
/// `M → 0` is exact.
pub fn rollup_tip(l: f64, ei: f64, m: f64) -> (f64, f64) {
    let theta = m * l / ei;
    if theta == 0.0 {
        return (l, 0.0);
    }
    let half = 0.5 * theta;
    (
        l * theta.sin() / theta,
        l * 2.0 * half.sin() * half.sin() / theta,
    )
}

/// Tip rotation `θ = M L / EI` [rad] of the roll-up ([`rollup_tip`]).
pub fn rollup_tip_rotation(l: f64, ei: f64, m: f64) -> f64 {
    m * l / ei
}

// ---------------------------------------------------------------------------------------------
// Cantilever under a tip shear force: the inextensible elastica
// ---------------------------------------------------------------------------------------------

/// Tip of a cantilever under a tip force perpendicular to its undeformed axis, in units of the
/// length `L` (dimensionless).
#[derive(Clone, Copy, Debug)]
pub struct ElasticaTip {
    /// Horizontal shortening `u / L = 1 − x_tip / L` [-] (positive: the tip moves towards the
    /// root).
    pub u: f64,
    /// Deflection `w / L` along the force [-].
    pub w: f64,
    /// Tip rotation `θ₀` [rad].
    pub rotation: f64,
}

/// Inextensible elastica of a cantilever of length `L` under a dead tip force `P` perpendicular to
/// the undeformed axis, load parameter `k = P L² / EI` [-], closed form in elliptic integrals
/// (Bisshopp & Drucker 1945, Q. Appl. Math. 3:272–275; Mattiasson 1981, Int. J. Numer. Meth. Eng.
/// 17:145–153):
///
/// `√k = K(p) − F(φ₁, p)`, `p² = (1 + sin θ₀)/2`, `sin φ₁ = 1 / (p √2)`,
/// `x_tip / L = √(2 sin θ₀ / k)`, `w / L = 1 − 2 (E(p) − E(φ₁, p)) / √k`.
///
/// The tip rotation `θ₀` is found by bisection to machine precision; the elliptic integrals are
/// Carlson's symmetric forms (Carlson 1995, Numer. Algorithms 10:13–26). Valid for `k > 0`.
pub fn elastica_tip_shear(k: f64) -> ElasticaTip {
    assert!(k > 0.0, "load parameter k = P L^2 / EI must be positive");
    let sk = k.sqrt();
    let residual = |theta0: f64| {
        let (p, phi1) = elastica_modulus(theta0);
        ellint_f(0.5 * PI, p) - ellint_f(phi1, p) - sk
    };
    let (mut lo, mut hi) = (0.0, 0.5 * PI);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if residual(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let theta0 = 0.5 * (lo + hi);
    let (p, phi1) = elastica_modulus(theta0);
    let x = (2.0 * theta0.sin() / k).sqrt();
    let w = 1.0 - 2.0 * (ellint_e(0.5 * PI, p) - ellint_e(phi1, p)) / sk;
    ElasticaTip {
        u: 1.0 - x,
        w,
        rotation: theta0,
    }
}

/// Modulus `p` and lower amplitude `φ₁` of the elastica for the tip rotation `theta0`.
fn elastica_modulus(theta0: f64) -> (f64, f64) {
    let p = (0.5 * (1.0 + theta0.sin())).sqrt();
    let s = (FRAC_1_SQRT_2 / p).min(1.0);
    (p, s.asin())
}

/// Incomplete elliptic integral of the first kind `F(φ, p) = ∫₀^φ dt / √(1 − p² sin² t)`,
/// `0 ≤ φ ≤ π/2`, from Carlson's `R_F`.
fn ellint_f(phi: f64, p: f64) -> f64 {
    let (s, c) = phi.sin_cos();
    s * carlson_rf(c * c, 1.0 - p * p * s * s, 1.0)
}

/// Incomplete elliptic integral of the second kind `E(φ, p) = ∫₀^φ √(1 − p² sin² t) dt`,
/// `0 ≤ φ ≤ π/2`, from Carlson's `R_F` and `R_D`.
fn ellint_e(phi: f64, p: f64) -> f64 {
    let (s, c) = phi.sin_cos();
    let (x, y) = (c * c, 1.0 - p * p * s * s);
    s * carlson_rf(x, y, 1.0) - p * p * s * s * s / 3.0 * carlson_rd(x, y, 1.0)
}

/// Carlson's symmetric integral `R_F(x, y, z)` by duplication (Carlson 1995, Algorithm 1).
fn carlson_rf(x: f64, y: f64, z: f64) -> f64 {
    let (mut x, mut y, mut z) = (x, y, z);
    loop {
        let mu = (x + y + z) / 3.0;
        let (dx, dy, dz) = (1.0 - x / mu, 1.0 - y / mu, 1.0 - z / mu);
        if dx.abs().max(dy.abs()).max(dz.abs()) < 1e-4 {
            let e2 = dx * dy - dz * dz;
            let e3 = dx * dy * dz;
            return (1.0 + (e2 / 24.0 - 0.1 - 3.0 / 44.0 * e3) * e2 + e3 / 14.0) / mu.sqrt();
        }
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * (sy + sz) + sy * sz;
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        z = 0.25 * (z + lambda);
    }
}

/// Carlson's symmetric integral `R_D(x, y, z)` by duplication (Carlson 1995, Algorithm 4).
fn carlson_rd(x: f64, y: f64, z: f64) -> f64 {
    let (mut x, mut y, mut z) = (x, y, z);
    let (mut sum, mut fac) = (0.0, 1.0);
    loop {
        let mu = 0.2 * (x + y + 3.0 * z);
        let (dx, dy, dz) = ((mu - x) / mu, (mu - y) / mu, (mu - z) / mu);
        if dx.abs().max(dy.abs()).max(dz.abs()) < 1e-4 {
            let ea = dx * dy;
            let eb = dz * dz;
            let ec = ea - eb;
            let ed = ea - 6.0 * eb;
            let ee = ed + ec + ec;
            let (c1, c2, c3, c4) = (3.0 / 14.0, 1.0 / 6.0, 9.0 / 22.0, 3.0 / 26.0);
            let (c5, c6) = (0.25 * c3, 1.5 * c4);
            let series = 1.0
                + ed * (-c1 + c5 * ed - c6 * dz * ee)
                + dz * (c2 * ee + dz * (-c3 * ec + dz * c4 * ea));
            return 3.0 * sum + fac * series / (mu * mu.sqrt());
        }
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * (sy + sz) + sy * sz;
        sum += fac / (sz * (z + lambda));
        fac *= 0.25;
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        z = 0.25 * (z + lambda);
    }
}

/// The same elastica as [`elastica_tip_shear`] solved independently by shooting: RK4 with `steps`
/// equal steps on `θ'' = −k cos θ` (arc length scaled by `L`), `θ(0) = 0`, the root curvature
/// `θ'(0)` found by Newton's method (derivative from the variational equation) so that the free
/// end carries no moment, `θ'(1) = 0`, with the load raised in 10 increments as continuation.
/// The tip position integrates `x' = cos θ`, `z' = sin θ` alongside. The RK4 error is `∝ steps⁻⁴`;
/// with 4000 steps it agrees with the elliptic form to 1e-14 for `k ≤ 15` (measured).
pub fn elastica_tip_shear_shooting(k: f64, steps: usize) -> ElasticaTip {
    assert!(k > 0.0 && steps > 0);
    let increments = 10;
    // Linear theory at the first increment: root curvature P L / EI.
    let mut c = k / increments as f64;
    for j in 1..=increments {
        let kj = k * j as f64 / increments as f64;
        let mut converged = false;
        for _ in 0..50 {
            let end = shoot(kj, c, steps);
            let (res, dres) = (end[1], end[3]);
            let dc = -res / dres;
            c += dc;
            if dc.abs() < 1e-14 * (1.0 + c.abs()) {
                converged = true;
                break;
            }
        }
        assert!(converged, "elastica shooting did not converge at k = {kj}");
    }
    let state = shoot(k, c, steps);
    ElasticaTip {
        u: 1.0 - state[4],
        w: state[5],
        rotation: state[0],
    }
}

/// Integrates `[θ, θ', ψ, ψ', x, z]` from `s = 0` to `1` (RK4, `steps` steps) for the root
/// curvature `c`; `ψ = ∂θ/∂c` obeys `ψ'' = k sin θ ψ`.
fn shoot(k: f64, c: f64, steps: usize) -> [f64; 6] {
    let rhs = |y: &[f64; 6]| -> [f64; 6] {
        let (s, co) = y[0].sin_cos();
        [y[1], -k * co, y[3], k * s * y[2], co, s]
    };
    let h = 1.0 / steps as f64;
    let mut y = [0.0, c, 0.0, 1.0, 0.0, 0.0];
    let axpy = |y: &[f64; 6], a: f64, d: &[f64; 6]| -> [f64; 6] {
        let mut out = *y;
        for i in 0..6 {
            out[i] += a * d[i];
        }
        out
    };
    for _ in 0..steps {
        let k1 = rhs(&y);
        let k2 = rhs(&axpy(&y, 0.5 * h, &k1));
        let k3 = rhs(&axpy(&y, 0.5 * h, &k2));
        let k4 = rhs(&axpy(&y, h, &k3));
        for i in 0..6 {
            y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
    y
}
