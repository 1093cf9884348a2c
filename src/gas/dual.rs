//! Forward-mode dual numbers with a fixed number of derivative directions: the residual of the
//! inner gas solve is written once and gives its exact Jacobian (and the derivative with respect
//! to the bag volume) by the chain rule, without allocation.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A value and its derivatives along `N` directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Dual<const N: usize> {
    /// The value.
    pub v: f64,
    /// The derivatives.
    pub d: [f64; N],
}

impl<const N: usize> Dual<N> {
    /// A constant (all derivatives zero).
    pub fn c(v: f64) -> Self {
        Self { v, d: [0.0; N] }
    }
    /// The independent variable number `i` with value `v`.
    pub fn var(v: f64, i: usize) -> Self {
        let mut d = [0.0; N];
        d[i] = 1.0;
        Self { v, d }
    }
    /// `f(self)` given `f(v)` and `f'(v)`.
    pub fn map(self, f: f64, df: f64) -> Self {
        let mut d = self.d;
        for x in &mut d {
            *x *= df;
        }
        Self { v: f, d }
    }
    /// e^x.
    pub fn exp(self) -> Self {
        let e = self.v.exp();
        self.map(e, e)
    }
    /// ln x.
    pub fn ln(self) -> Self {
        self.map(self.v.ln(), 1.0 / self.v)
    }
    /// √x.
    pub fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        self.map(s, 0.5 / s)
    }
    /// Whether the value and every derivative are finite.
    pub fn is_finite(&self) -> bool {
        self.v.is_finite() && self.d.iter().all(|x| x.is_finite())
    }
}

impl<const N: usize> Add for Dual<N> {
    type Output = Self;
    fn add(mut self, o: Self) -> Self {
        self.v += o.v;
        for i in 0..N {
            self.d[i] += o.d[i];
        }
        self
    }
}
impl<const N: usize> Sub for Dual<N> {
    type Output = Self;
    fn sub(mut self, o: Self) -> Self {
        self.v -= o.v;
        for i in 0..N {
            self.d[i] -= o.d[i];
        }
        self
    }
}
impl<const N: usize> Mul for Dual<N> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        let mut d = [0.0; N];
        for i in 0..N {
            d[i] = self.d[i] * o.v + self.v * o.d[i];
        }
        Self { v: self.v * o.v, d }
    }
}
impl<const N: usize> Div for Dual<N> {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        let q = self.v / o.v;
        let mut d = [0.0; N];
        for i in 0..N {
            d[i] = (self.d[i] - q * o.d[i]) / o.v;
        }
        Self { v: q, d }
    }
}
impl<const N: usize> Neg for Dual<N> {
    type Output = Self;
    fn neg(self) -> Self {
        self.map(-self.v, -1.0)
    }
}
impl<const N: usize> Add<f64> for Dual<N> {
    type Output = Self;
    fn add(mut self, o: f64) -> Self {
        self.v += o;
        self
    }
}
impl<const N: usize> Sub<f64> for Dual<N> {
    type Output = Self;
    fn sub(mut self, o: f64) -> Self {
        self.v -= o;
        self
    }
}
impl<const N: usize> Mul<f64> for Dual<N> {
    type Output = Self;
    fn mul(self, o: f64) -> Self {
        self.map(self.v * o, o)
    }
}
impl<const N: usize> Div<f64> for Dual<N> {
    type Output = Self;
    fn div(self, o: f64) -> Self {
        self.map(self.v / o, 1.0 / o)
    }
}
impl<const N: usize> Mul<Dual<N>> for f64 {
    type Output = Dual<N>;
    fn mul(self, o: Dual<N>) -> Dual<N> {
        o * self
    }
}
impl<const N: usize> Sub<Dual<N>> for f64 {
    type Output = Dual<N>;
    fn sub(self, o: Dual<N>) -> Dual<N> {
        -o + self
    }
}
impl<const N: usize> Div<Dual<N>> for f64 {
    type Output = Dual<N>;
    fn div(self, o: Dual<N>) -> Dual<N> {
        let q = self / o.v;
        o.map(q, -q / o.v)
    }
}

#[cfg(test)]
mod tests {
    use super::Dual;

    /// The chain rule of every operation against central differences of the f64 expression.
    #[test]
    fn derivatives_match_finite_differences() {
        let f = |x: Dual<2>, y: Dual<2>| {
            ((x * y + 3.0).ln() / (2.0 - y) + (x / y).sqrt() * 0.5).exp() - 1.0 / x + x * 2.0
                - y / 4.0
        };
        let (x0, y0) = (1.3, 0.7);
        let a = f(Dual::var(x0, 0), Dual::var(y0, 1));
        let h = 1e-6;
        let fx =
            (f(Dual::c(x0 + h), Dual::c(y0)).v - f(Dual::c(x0 - h), Dual::c(y0)).v) / (2.0 * h);
        let fy =
            (f(Dual::c(x0), Dual::c(y0 + h)).v - f(Dual::c(x0), Dual::c(y0 - h)).v) / (2.0 * h);
        assert!(
            (a.d[0] - fx).abs() < 1e-8 * fx.abs().max(1.0),
            "{} vs {fx}",
            a.d[0]
        );
        assert!(
            (a.d[1] - fy).abs() < 1e-8 * fy.abs().max(1.0),
            "{} vs {fy}",
            a.d[1]
        );
    }
}
