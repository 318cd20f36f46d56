//! Parameter homotopy continuation for square polynomial systems (Sommese & Wampler, *The
//! Numerical Solution of Systems of Polynomials*, 2005, ch. 7; Morgan & Sommese 1989).
//!
//! A family $F(z; p) = 0$ of $n$ polynomial equations in $n$ unknowns $z \in \mathbb C^n$
//! with parameters $p \in \mathbb C^m$ has, for generic $p$, the same number $N$ of isolated
//! solutions; for any particular $p^*$ every isolated solution is the end of one of the $N$
//! paths of (eq. H1)
//! $$H(z, s) = F\big(z;\ p_0 + s\,(p^* - p_0)\big) = 0,\qquad s: 0 \to 1,$$
//! started at the solutions of a generic complex $p_0$ (the segment misses the discriminant
//! locus with probability one). The families here are quadratic in $z$ and in $p$
//! ([`QuadraticFamily`]): their quadratic forms are read once per segment (eq. H2) as
//! polynomials of degree two in $s$, so $F$, $F_z$ and $\partial_s F$ along the path cost a few
//! matrix–vector products each and are exact. [`track`] follows one path: along
//! $\dot z = -F_z^{-1}\partial_s F$ by a fourth-order Runge–Kutta predictor, Newton's corrector at each step,
//! step halved when the corrector does not contract and doubled after three successes; a path
//! whose $\lvert z\rvert$ grows past a bound goes to infinity, one whose step underflows has
//! failed, and the endpoint is refined by Newton and classed regular or singular by the
//! condition of $F_z$ there. [`monodromy`] finds the $N$ solutions of $p_0$ from one: every
//! known solution is tracked around loops $p_0 \to p_1 \to p_2 \to p_0$ through random
//! complex parameters, which permutes the solutions; endpoints not yet known are added, until
//! a number of consecutive loops adds none (the count is then a lower bound that a trace test
//! or a known generic count confirms).
//!
//! Every loop is bounded (steps per path, loops, solutions) and every random draw comes from a
//! seeded ChaCha8 stream, so a run is reproducible bit for bit.

use nalgebra::{Complex, DMatrix, DVector};
use pkm_traits::{BlockKernel, run_block};
use rand::Rng;
use rayon::prelude::*;

/// A complex number.
pub type C64 = Complex<f64>;

/// A square family $F(z; p)$: $n$ equations in $n$ unknowns, each of degree at most two in
/// $z$ and at most two in $p$ (a system of higher degree is written so with auxiliary
/// unknowns, $y = x^2$).
pub trait QuadraticFamily {
    /// $n$: unknowns and equations.
    fn unknowns(&self) -> usize;
    /// $F(z; p)$ into `f` ($n$ entries).
    fn residual(&self, z: &[C64], p: &[C64], f: &mut [C64]);
}

/// The quadratic forms $F_k(z) = z^\top A_k z + b_k\cdot z + c_k$ of a family at one point of
/// parameter space, read from $1 + 2n + n(n-1)/2$ evaluations (eq. H2):
/// $c = F(0)$, $A_{jj} = \tfrac12(F(e_j) + F(-e_j)) - c$, $b_j = \tfrac12(F(e_j) - F(-e_j))$,
/// $2A_{jk} = F(e_j + e_k) - F(e_j) - F(e_k) + c$. Stored flat: $A_k$ row-major one after the
/// other ($A_k$ symmetric), its real and imaginary parts apart so that $A_k z$ runs as
/// independent lanes over the rows (vectorised, each lane summing in the same order: the
/// same bits at any vector width); $b_k$ as rows.
#[derive(Debug, Clone, PartialEq)]
struct Forms {
    n: usize,
    a_re: Vec<f64>,
    a_im: Vec<f64>,
    b: Vec<C64>,
    c: Vec<C64>,
}

const ZERO: C64 = C64::new(0.0, 0.0);

impl Forms {
    fn read<S: QuadraticFamily + ?Sized>(family: &S, p: &[C64]) -> Self {
        let n = family.unknowns();
        let mut z = vec![ZERO; n];
        let at = |z: &[C64]| {
            let mut f = vec![ZERO; n];
            family.residual(z, p, &mut f);
            f
        };
        let c = at(&z);
        let one = C64::new(1.0, 0.0);
        let (mut plus, mut minus) = (Vec::with_capacity(n), Vec::with_capacity(n));
        for j in 0..n {
            z[j] = one;
            plus.push(at(&z));
            z[j] = -one;
            minus.push(at(&z));
            z[j] = ZERO;
        }
        let mut a = vec![ZERO; n * n * n];
        let mut b = vec![ZERO; n * n];
        for j in 0..n {
            for k in 0..n {
                a[k * n * n + j * n + j] = (plus[j][k] + minus[j][k]) * 0.5 - c[k];
                b[k * n + j] = (plus[j][k] - minus[j][k]) * 0.5;
            }
            for l in j + 1..n {
                z[j] = one;
                z[l] = one;
                let both = at(&z);
                z[j] = ZERO;
                z[l] = ZERO;
                for k in 0..n {
                    let v = (both[k] - plus[j][k] - plus[l][k] + c[k]) * 0.5;
                    a[k * n * n + j * n + l] = v;
                    a[k * n * n + l * n + j] = v;
                }
            }
        }
        Self {
            n,
            a_re: a.iter().map(|v| v.re).collect(),
            a_im: a.iter().map(|v| v.im).collect(),
            b,
            c,
        }
    }

    /// `self` set to $\alpha X + \beta Y + \gamma Z$, entry by entry.
    fn combine(&mut self, weights: [f64; 3], forms: [&Self; 3]) {
        let [x, y, w] = forms;
        let mix = |out: &mut [f64], a: &[f64], b: &[f64], c: &[f64]| {
            for (((o, a), b), c) in out.iter_mut().zip(a).zip(b).zip(c) {
                *o = a * weights[0] + b * weights[1] + c * weights[2];
            }
        };
        let mix_complex = |out: &mut [C64], a: &[C64], b: &[C64], c: &[C64]| {
            for (((o, a), b), c) in out.iter_mut().zip(a).zip(b).zip(c) {
                *o = a * weights[0] + b * weights[1] + c * weights[2];
            }
        };
        mix(&mut self.a_re, &x.a_re, &y.a_re, &w.a_re);
        mix(&mut self.a_im, &x.a_im, &y.a_im, &w.a_im);
        mix_complex(&mut self.b, &x.b, &y.b, &w.b);
        mix_complex(&mut self.c, &x.c, &y.c, &w.c);
    }

    /// The products $A_k v$ of every form with `v`, into `out` ($n \times n$, row $k$ the
    /// vector $A_k v$), each summed over the columns $l$ in order, row $j$ taking
    /// $A_{lj} = A_{jl}$.
    fn products(&self, v: &[C64], out: &mut [C64]) {
        let n = self.n;
        out.fill(ZERO);
        for k in 0..n {
            let row_out = &mut out[k * n..(k + 1) * n];
            for (l, vl) in v.iter().enumerate() {
                let at = k * n * n + l * n;
                let (row_re, row_im) = (&self.a_re[at..at + n], &self.a_im[at..at + n]);
                for ((o, r), i) in row_out.iter_mut().zip(row_re).zip(row_im) {
                    *o = C64::new(
                        o.re + (r * vl.re - i * vl.im),
                        o.im + (r * vl.im + i * vl.re),
                    );
                }
            }
        }
    }

    /// $F(z)$ into `f` and, when given, $F_z = 2A_k z + b_k$ (rows, flat) into `jacobian`.
    /// Up to eight unknowns the size is a constant, so the sums stay in registers, on the
    /// widest vector path of the processor (`pkm_traits::run_block`): the same operations in
    /// the same order, so the same bits as the general size on every path. `az` is the
    /// workspace of the general size (the products $A_k z$).
    fn at(&self, z: &[C64], f: &mut [C64], jacobian: Option<&mut [C64]>, az: &mut [C64]) {
        match self.n {
            1 => self.at_fixed::<1>(z, f, jacobian),
            2 => self.at_fixed::<2>(z, f, jacobian),
            3 => self.at_fixed::<3>(z, f, jacobian),
            4 => self.at_fixed::<4>(z, f, jacobian),
            5 => self.at_fixed::<5>(z, f, jacobian),
            6 => self.at_fixed::<6>(z, f, jacobian),
            7 => self.at_fixed::<7>(z, f, jacobian),
            8 => self.at_fixed::<8>(z, f, jacobian),
            _ => self.at_any(z, f, jacobian, az),
        }
    }

    /// [`Forms::at`] for `N` unknowns.
    fn at_fixed<const N: usize>(&self, z: &[C64], f: &mut [C64], jacobian: Option<&mut [C64]>) {
        let kernel = FixedAt::<N> {
            forms: self,
            z: std::array::from_fn(|j| z[j]),
        };
        let (values, rows) = run_block(&kernel);
        f.copy_from_slice(&values);
        if let Some(jacobian) = jacobian {
            for (out, row) in jacobian.chunks_exact_mut(N).zip(rows) {
                out.copy_from_slice(&row);
            }
        }
    }

    /// [`Forms::at`] for any number of unknowns.
    fn at_any(&self, z: &[C64], f: &mut [C64], mut jacobian: Option<&mut [C64]>, az: &mut [C64]) {
        let n = self.n;
        self.products(z, az);
        for k in 0..n {
            let b = &self.b[k * n..(k + 1) * n];
            let mut value = self.c[k];
            for j in 0..n {
                let product = az[k * n + j];
                value += z[j] * product + b[j] * z[j];
                if let Some(jac) = jacobian.as_deref_mut() {
                    jac[k * n + j] = product * 2.0 + b[j];
                }
            }
            f[k] = value;
        }
    }
}

/// [`Forms::at`] of `N` unknowns as a block kernel: the values $F_k(z)$ and the rows of $F_z$.
struct FixedAt<'a, const N: usize> {
    forms: &'a Forms,
    z: [C64; N],
}

impl<const N: usize> BlockKernel for FixedAt<'_, N> {
    type Output = ([C64; N], [[C64; N]; N]);

    #[inline(always)]
    fn run(&self) -> Self::Output {
        let (mut values, mut jacobian) = ([ZERO; N], [[ZERO; N]; N]);
        let forms = self.forms;
        for (k, (value, jacobian)) in values.iter_mut().zip(&mut jacobian).enumerate() {
            let (mut re, mut im) = ([0.0; N], [0.0; N]);
            for (l, zl) in self.z.iter().enumerate() {
                let at = k * N * N + l * N;
                let row = forms.a_re[at..at + N].iter().zip(&forms.a_im[at..at + N]);
                for ((re, im), (r, i)) in re.iter_mut().zip(im.iter_mut()).zip(row) {
                    *re += r * zl.re - i * zl.im;
                    *im += r * zl.im + i * zl.re;
                }
            }
            let b = &forms.b[k * N..(k + 1) * N];
            *value = forms.c[k];
            for j in 0..N {
                let product = C64::new(re[j], im[j]);
                *value += self.z[j] * product + b[j] * self.z[j];
                jacobian[j] = product * 2.0 + b[j];
            }
        }
        (values, jacobian)
    }
}

/// [`solve_in_place`] of `N` unknowns as a block kernel (the same operations in the same order).
struct FixedSolve<const N: usize> {
    a: [[C64; N]; N],
    rhs: [C64; N],
}

impl<const N: usize> BlockKernel for FixedSolve<N> {
    type Output = Option<[C64; N]>;

    #[inline(always)]
    fn run(&self) -> Self::Output {
        let (mut a, mut rhs) = (self.a, self.rhs);
        for col in 0..N {
            let mut pivot = col;
            for i in col + 1..N {
                // `max_by` keeps the last of equal maxima.
                if a[i][col].norm_sqr() >= a[pivot][col].norm_sqr() {
                    pivot = i;
                }
            }
            if !(a[pivot][col].norm_sqr() > 0.0) {
                return None;
            }
            if pivot != col {
                a.swap(col, pivot);
                rhs.swap(col, pivot);
            }
            let inverse = C64::new(1.0, 0.0) / a[col][col];
            let pivot_row = a[col];
            for row in col + 1..N {
                let factor = a[row][col] * inverse;
                if factor == ZERO {
                    continue;
                }
                for k in col..N {
                    a[row][k] -= factor * pivot_row[k];
                }
                rhs[row] -= factor * rhs[col];
            }
        }
        for row in (0..N).rev() {
            let mut sum = rhs[row];
            for k in row + 1..N {
                sum -= a[row][k] * rhs[k];
            }
            rhs[row] = sum / a[row][row];
        }
        rhs.iter()
            .all(|c| c.re.is_finite() && c.im.is_finite())
            .then_some(rhs)
    }
}

/// [`solve_in_place`] for `N` unknowns on the widest vector path of the processor.
fn solve_fixed<const N: usize>(a: &[C64], rhs: &mut [C64]) -> bool {
    let mut kernel = FixedSolve::<N> {
        a: [[ZERO; N]; N],
        rhs: std::array::from_fn(|j| rhs[j]),
    };
    for (row, values) in kernel.a.iter_mut().zip(a.chunks_exact(N)) {
        row.copy_from_slice(values);
    }
    match run_block(&kernel) {
        Some(x) => {
            rhs.copy_from_slice(&x);
            true
        }
        None => false,
    }
}

/// Solves the $n \times n$ system `a x = rhs` (row-major, overwritten) in place by Gaussian
/// elimination with partial pivoting; `false` for a zero pivot or a non-finite solution.
fn solve_in_place(a: &mut [C64], rhs: &mut [C64], n: usize) -> bool {
    for col in 0..n {
        let pivot = (col..n)
            .max_by(|&i, &j| {
                a[i * n + col]
                    .norm_sqr()
                    .total_cmp(&a[j * n + col].norm_sqr())
            })
            .unwrap_or(col);
        if !(a[pivot * n + col].norm_sqr() > 0.0) {
            return false;
        }
        if pivot != col {
            for k in 0..n {
                a.swap(col * n + k, pivot * n + k);
            }
            rhs.swap(col, pivot);
        }
        let inverse = C64::new(1.0, 0.0) / a[col * n + col];
        for row in col + 1..n {
            let factor = a[row * n + col] * inverse;
            if factor == ZERO {
                continue;
            }
            for k in col..n {
                let v = a[col * n + k];
                a[row * n + k] -= factor * v;
            }
            let v = rhs[col];
            rhs[row] -= factor * v;
        }
    }
    for row in (0..n).rev() {
        let mut sum = rhs[row];
        for k in row + 1..n {
            sum -= a[row * n + k] * rhs[k];
        }
        rhs[row] = sum / a[row * n + row];
    }
    rhs.iter().all(|c| c.re.is_finite() && c.im.is_finite())
}

/// Settings of [`track`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackSettings {
    /// First step in $s$. Default 0.02.
    pub initial_step: f64,
    /// Largest step. Default 0.1.
    pub max_step: f64,
    /// Smallest step before the path is declared failed. Default 1e-12.
    pub min_step: f64,
    /// Steps (accepted or not) before the path is declared failed. Default 20 000.
    pub max_steps: usize,
    /// A path whose $\lvert z\rvert_\infty$ passes this goes to infinity. Default 1e8.
    pub infinity: f64,
    /// An endpoint with $\sigma_{\min}/\sigma_{\max}(F_z)$ below this is singular. Default 1e-7:
    /// a double root is reached only to $\sqrt\varepsilon$, where its condition is about
    /// $\sqrt\varepsilon \approx 1.5\times 10^{-8}$.
    pub singular: f64,
    /// A path that stalls within this of $s = 1$ is finished by Newton at $s = 1$ (a singular
    /// endpoint). Default 1e-3.
    pub endgame: f64,
}

impl Default for TrackSettings {
    fn default() -> Self {
        Self {
            initial_step: 0.02,
            max_step: 0.1,
            min_step: 1e-12,
            max_steps: 20_000,
            infinity: 1e8,
            singular: 1e-7,
            endgame: 1e-3,
        }
    }
}

/// How a path ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Endpoint {
    /// A nonsingular solution at $s = 1$, refined by Newton.
    Regular(DVector<C64>),
    /// A solution at $s = 1$ where $F_z$ is singular (a multiple root, a positive-dimensional
    /// component): its condition is below [`TrackSettings::singular`].
    Singular(DVector<C64>),
    /// $\lvert z\rvert$ passed [`TrackSettings::infinity`] at `s`: no finite solution.
    Infinity {
        /// Where.
        s: f64,
    },
    /// The tracker could not follow the path (step underflow near a singularity, too many
    /// steps, a system that does not evaluate), at `s`.
    Failed {
        /// Where.
        s: f64,
        /// Why, in words.
        reason: &'static str,
        /// The last point reached.
        at: DVector<C64>,
    },
}

/// One path's work: its end and the steps it took.
#[derive(Debug, Clone, PartialEq)]
pub struct Path {
    /// How it ended.
    pub end: Endpoint,
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps.
    pub rejected: usize,
}

/// A segment's forms as polynomials in $s$: the forms are of degree two in the parameters,
/// so in $s$, $Q(s) = Q_0 + s\,Q_1 + s^2 Q_2$ from the forms at $s = 0, \tfrac12, 1$. Read
/// once and shared by every path of the segment.
#[derive(Debug)]
pub struct SegmentForms {
    terms: [Forms; 3],
}

impl SegmentForms {
    /// The forms of `system` along the segment from the parameters `from` to `to`.
    pub fn new<S: QuadraticFamily + ?Sized>(system: &S, from: &[C64], to: &[C64]) -> Self {
        let mid: Vec<C64> = from.iter().zip(to).map(|(a, b)| (a + b) * 0.5).collect();
        let (f0, fh, f1) = (
            Forms::read(system, from),
            Forms::read(system, &mid),
            Forms::read(system, to),
        );
        let mut terms = [f0.clone(), f0.clone(), f0.clone()];
        terms[1].combine([-3.0, 4.0, -1.0], [&f0, &fh, &f1]);
        terms[2].combine([2.0, -4.0, 2.0], [&f0, &fh, &f1]);
        Self { terms }
    }
}

/// One path's walk along a segment: the forms at its current $s$ and the tracker's workspace.
struct Segment<'a> {
    terms: &'a [Forms; 3],
    at_s: Forms,
    s: f64,
    f: DVector<C64>,
    jacobian: Vec<C64>,
    scratch: Vec<C64>,
    products: Vec<C64>,
}

impl<'a> Segment<'a> {
    fn new(forms: &'a SegmentForms) -> Self {
        let n = forms.terms[0].n;
        Self {
            at_s: forms.terms[0].clone(),
            terms: &forms.terms,
            s: 0.0,
            f: DVector::zeros(n),
            jacobian: vec![ZERO; n * n],
            scratch: vec![ZERO; n],
            products: vec![ZERO; n * n],
        }
    }

    /// The forms at `s` (kept for the last `s`).
    fn move_to(&mut self, s: f64) {
        if s.to_bits() != self.s.to_bits() {
            let [q0, q1, q2] = self.terms;
            self.at_s.combine([1.0, s, s * s], [q0, q1, q2]);
            self.s = s;
        }
    }

    /// $F$ and $F_z$ at $(z, s)$.
    fn at(&mut self, z: &DVector<C64>, s: f64) {
        self.move_to(s);
        self.at_s.at(
            z.as_slice(),
            self.f.as_mut_slice(),
            Some(&mut self.jacobian),
            &mut self.products,
        );
    }

    /// $F_z^{-1} r$ at the last point evaluated; `None` when singular. Up to eight unknowns
    /// on the widest vector path ([`FixedSolve`]), the same bits.
    fn solve(&mut self, mut rhs: DVector<C64>) -> Option<DVector<C64>> {
        let n = rhs.len();
        let (a, x) = (&self.jacobian, rhs.as_mut_slice());
        let solved = match n {
            1 => solve_fixed::<1>(a, x),
            2 => solve_fixed::<2>(a, x),
            3 => solve_fixed::<3>(a, x),
            4 => solve_fixed::<4>(a, x),
            5 => solve_fixed::<5>(a, x),
            6 => solve_fixed::<6>(a, x),
            7 => solve_fixed::<7>(a, x),
            8 => solve_fixed::<8>(a, x),
            _ => {
                self.scratch.clear();
                self.scratch.extend_from_slice(a);
                solve_in_place(&mut self.scratch, x, n)
            }
        };
        solved.then_some(rhs)
    }

    /// $\dot z = -F_z^{-1}\,\partial_s F$ at $(z, s)$, with $\partial_s F = Q_1(z) + 2s\,Q_2(z)$
    /// (the $z$-free parts included) exactly.
    fn tangent(&mut self, z: &DVector<C64>, s: f64) -> Option<DVector<C64>> {
        let n = z.len();
        let (mut d1, mut d2) = (DVector::zeros(n), DVector::zeros(n));
        let [_, q1, q2] = self.terms;
        q1.at(z.as_slice(), d1.as_mut_slice(), None, &mut self.products);
        q2.at(z.as_slice(), d2.as_mut_slice(), None, &mut self.products);
        let ds = d1 + d2 * C64::new(2.0 * s, 0.0);
        self.at(z, s);
        self.solve(-ds)
    }

    /// One Newton step at $(z, s)$: the correction.
    fn newton(&mut self, z: &DVector<C64>, s: f64) -> Option<DVector<C64>> {
        self.at(z, s);
        let rhs = -&self.f;
        self.solve(rhs)
    }

    /// $\sigma_{\min}/\sigma_{\max}$ of $F_z$ at the last point evaluated.
    fn condition(&self) -> f64 {
        let n = self.f.len();
        let sv = DMatrix::from_row_slice(n, n, &self.jacobian).singular_values();
        sv.min() / sv.max().max(1e-300)
    }
}

/// $\lvert z\rvert_\infty$ over real and imaginary parts.
fn norm(z: &DVector<C64>) -> f64 {
    z.iter()
        .map(|c| c.re.abs().max(c.im.abs()))
        .fold(0.0, f64::max)
}

/// Newton's corrector at $s$ from the prediction `z`: up to three steps, each at most half the
/// last, converged when the step is below 1e-9 of $\max(1, \lvert z\rvert)$.
fn correct(segment: &mut Segment, mut z: DVector<C64>, s: f64) -> Option<DVector<C64>> {
    let mut last = f64::INFINITY;
    for _ in 0..3 {
        let d = segment.newton(&z, s)?;
        let size = norm(&d);
        if !(size <= 0.5 * last) {
            return None;
        }
        z += d;
        if size <= 1e-9 * norm(&z).max(1.0) {
            return Some(z);
        }
        last = size;
    }
    None
}

/// The fourth-order Runge–Kutta prediction of $z$ at $s + h$.
fn predict(segment: &mut Segment, z: &DVector<C64>, s: f64, h: f64) -> Option<DVector<C64>> {
    let half = C64::new(h / 2.0, 0.0);
    let k1 = segment.tangent(z, s)?;
    let k2 = segment.tangent(&(z + &k1 * half), s + h / 2.0)?;
    let k3 = segment.tangent(&(z + &k2 * half), s + h / 2.0)?;
    let k4 = segment.tangent(&(z + &k3 * C64::new(h, 0.0)), s + h)?;
    Some(z + (k1 + k2 * C64::new(2.0, 0.0) + k3 * C64::new(2.0, 0.0) + k4) * C64::new(h / 6.0, 0.0))
}

/// Follows the solution `start` of $F(z; p_{\text{from}})$ to $p_{\text{to}}$ along the
/// segment of eq. H1 (module documentation).
pub fn track<S: QuadraticFamily + ?Sized>(
    system: &S,
    start: &DVector<C64>,
    from: &[C64],
    to: &[C64],
    settings: &TrackSettings,
) -> Path {
    track_on(&SegmentForms::new(system, from, to), start, settings)
}

/// [`track`] on the forms of a segment read beforehand (shared by the paths of the segment).
pub fn track_on(forms: &SegmentForms, start: &DVector<C64>, settings: &TrackSettings) -> Path {
    let mut segment = Segment::new(forms);
    let (mut z, mut s, mut h) = (start.clone(), 0.0_f64, settings.initial_step);
    let (mut steps, mut rejected, mut streak) = (0, 0, 0);
    let bound = settings.infinity * norm(start).max(1.0);
    let failed = |s: f64, reason, at: &DVector<C64>, steps, rejected| Path {
        end: Endpoint::Failed {
            s,
            reason,
            at: at.clone(),
        },
        steps,
        rejected,
    };
    while s < 1.0 {
        if steps + rejected >= settings.max_steps {
            return failed(s, "too many steps", &z, steps, rejected);
        }
        let last = h >= 1.0 - s;
        let step = if last { 1.0 - s } else { h };
        let next = predict(&mut segment, &z, s, step)
            .and_then(|guess| correct(&mut segment, guess, s + step));
        match next {
            Some(corrected) => {
                z = corrected;
                s = if last { 1.0 } else { s + step };
                steps += 1;
                streak += 1;
                if streak >= 3 {
                    h = (2.0 * h).min(settings.max_step);
                    streak = 0;
                }
                if !(norm(&z) <= bound) {
                    return Path {
                        end: Endpoint::Infinity { s },
                        steps,
                        rejected,
                    };
                }
            }
            None => {
                rejected += 1;
                streak = 0;
                h *= 0.5;
                if h < settings.min_step {
                    if norm(&z) > 1e3 * norm(start).max(1.0) {
                        return Path {
                            end: Endpoint::Infinity { s },
                            steps,
                            rejected,
                        };
                    }
                    let finished = (s > 1.0 - settings.endgame)
                        .then(|| endgame(&mut segment, z.clone(), settings))
                        .flatten();
                    if let Some(end) = finished {
                        return Path {
                            end,
                            steps,
                            rejected,
                        };
                    }
                    let reason = "step size underflow (a singularity on the path or at its end)";
                    return failed(s, reason, &z, steps, rejected);
                }
            }
        }
    }
    Path {
        end: endpoint(&mut segment, z, settings),
        steps,
        rejected,
    }
}

/// [`track`] of every start, in parallel (rayon), in the order of `starts`: the same bits
/// whatever the number of threads (each path is computed alone).
pub fn track_many<S: QuadraticFamily + Sync + ?Sized>(
    system: &S,
    starts: &[DVector<C64>],
    from: &[C64],
    to: &[C64],
    settings: &TrackSettings,
) -> Vec<Path> {
    let forms = SegmentForms::new(system, from, to);
    starts
        .par_iter()
        .map(|z0| track_on(&forms, z0, settings))
        .collect()
}

/// [`track`] from `from` to `to` through the parameters `via` (two segments): the detour that
/// takes a path around a near-singularity of the straight segment (a random complex `via`
/// avoids the discriminant with probability one). Steps add up; the first segment's failure
/// is reported at $s = 0$ of the whole.
pub fn track_through<S: QuadraticFamily + ?Sized>(
    system: &S,
    start: &DVector<C64>,
    from: &[C64],
    via: &[C64],
    to: &[C64],
    settings: &TrackSettings,
) -> Path {
    let first = track(system, start, from, via, settings);
    let Endpoint::Regular(middle) = &first.end else {
        return match first.end {
            Endpoint::Failed { reason, at, .. } => Path {
                end: Endpoint::Failed { s: 0.0, reason, at },
                ..first
            },
            _ => Path {
                end: Endpoint::Failed {
                    s: 0.0,
                    reason: "the detour's first segment ended singular or at infinity",
                    at: start.clone(),
                },
                ..first
            },
        };
    };
    let second = track(system, middle, via, to, settings);
    Path {
        end: second.end,
        steps: first.steps + second.steps,
        rejected: first.rejected + second.rejected,
    }
}

/// A path that stalls within [`TrackSettings::endgame`] of its end (the solutions meeting
/// there: a multiple root, a positive-dimensional component): Newton at $s = 1$ from where it
/// stalled, up to 100 steps (linear convergence to a singular root), and the endpoint if
/// $\lvert F\rvert$ falls below 1e-10 of the system's scale; `None` otherwise.
fn endgame(
    segment: &mut Segment,
    mut z: DVector<C64>,
    settings: &TrackSettings,
) -> Option<Endpoint> {
    for _ in 0..100 {
        let d = segment.newton(&z, 1.0)?;
        z += &d;
        if norm(&d) <= 1e-12 * norm(&z).max(1.0) {
            break;
        }
    }
    segment.at(&z, 1.0);
    let scale = segment.at_s.c.iter().map(|c| c.norm()).fold(1.0, f64::max);
    (norm(&segment.f) <= 1e-10 * scale).then(|| endpoint(segment, z, settings))
}

/// The endpoint refined by up to eight Newton steps at $s = 1$ and classed: regular when
/// Newton's last step is below 1e-10 of the endpoint and the condition of $F_z$ there is above
/// [`TrackSettings::singular`], singular otherwise.
fn endpoint(segment: &mut Segment, mut z: DVector<C64>, settings: &TrackSettings) -> Endpoint {
    let mut last = f64::INFINITY;
    for _ in 0..8 {
        let Some(d) = segment.newton(&z, 1.0) else {
            break;
        };
        z += &d;
        last = norm(&d);
        if last <= 1e-15 * norm(&z).max(1.0) {
            break;
        }
    }
    segment.at(&z, 1.0);
    // Newton converges quadratically to a nonsingular root (within the eight steps from the
    // tracker's 1e-9, to the rounding of an ill-conditioned one) and linearly to a multiple
    // one, whose last step stays far above that.
    let quadratic = last <= 1e-10 * norm(&z).max(1.0);
    let condition = segment.condition();
    if !z.iter().all(|c| c.re.is_finite() && c.im.is_finite()) {
        Endpoint::Failed {
            s: 1.0,
            reason: "the endpoint does not evaluate",
            at: z,
        }
    } else if condition >= settings.singular && quadratic {
        Endpoint::Regular(z)
    } else {
        Endpoint::Singular(z)
    }
}

/// Settings of [`monodromy`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MonodromySettings {
    /// Consecutive loops that add no solution before the search stops. Default 5.
    pub stable_loops: usize,
    /// Most loops. Default 200.
    pub max_loops: usize,
    /// Most solutions kept (a bound on memory). Default 100 000.
    pub max_solutions: usize,
    /// Two solutions are one within this of $\max(1, \lvert z\rvert_\infty)$. Default 1e-6.
    pub distinct: f64,
    /// The path tracker's settings.
    pub track: TrackSettings,
}

impl Default for MonodromySettings {
    fn default() -> Self {
        Self {
            stable_loops: 5,
            max_loops: 200,
            max_solutions: 100_000,
            distinct: 1e-6,
            track: TrackSettings::default(),
        }
    }
}

/// The solutions of a generic member found by [`monodromy`].
#[derive(Debug, Clone, PartialEq)]
pub struct Monodromy {
    /// The parameters $p_0$.
    pub parameters: Vec<C64>,
    /// Its solutions found.
    pub solutions: Vec<DVector<C64>>,
    /// Loops run.
    pub loops: usize,
    /// Whether the search stopped because `stable_loops` consecutive loops added nothing
    /// (rather than at `max_loops` or `max_solutions`).
    pub stable: bool,
}

/// Every solution of $F(z; p_0)$ that loops from the solution `start` reach (module
/// documentation): loops $p_0 \to p_1 \to p_2 \to p_0$ through parameters drawn by `draw`
/// (random complex points of the same scale as $p_0$).
pub fn monodromy<S: QuadraticFamily + Sync + ?Sized, R: Rng>(
    system: &S,
    parameters: &[C64],
    start: DVector<C64>,
    settings: &MonodromySettings,
    rng: &mut R,
) -> Monodromy {
    let mut solutions = vec![start];
    let (mut loops, mut quiet) = (0, 0);
    let scale = parameters
        .iter()
        .map(|p| p.norm())
        .fold(0.0, f64::max)
        .max(1.0);
    while loops < settings.max_loops
        && quiet < settings.stable_loops
        && solutions.len() < settings.max_solutions
    {
        loops += 1;
        let mut draw = || -> Vec<C64> {
            parameters
                .iter()
                .map(|_| C64::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0)) * scale)
                .collect()
        };
        let (p1, p2) = (draw(), draw());
        let before = solutions.len();
        // Every known solution around the loop, in parallel; the new endpoints then added in
        // order, so the result does not depend on the number of threads.
        let around = [parameters, &p1, &p2, parameters];
        let legs: Vec<SegmentForms> = around
            .windows(2)
            .map(|leg| SegmentForms::new(system, leg[0], leg[1]))
            .collect();
        let ends: Vec<Option<DVector<C64>>> = solutions
            .par_iter()
            .map(|start| {
                let mut z = start.clone();
                for leg in &legs {
                    match track_on(leg, &z, &settings.track).end {
                        Endpoint::Regular(end) => z = end,
                        _ => return None,
                    }
                }
                Some(z)
            })
            .collect();
        for z in ends.into_iter().flatten() {
            if solutions.len() >= settings.max_solutions {
                break;
            }
            if !contains(&solutions, &z, settings.distinct) {
                solutions.push(z);
            }
        }
        quiet = if solutions.len() > before {
            0
        } else {
            quiet + 1
        };
    }
    Monodromy {
        parameters: parameters.to_vec(),
        stable: quiet >= settings.stable_loops,
        solutions,
        loops,
    }
}

/// Whether `z` is within `tolerance` (relative) of one of `known`.
pub fn contains(known: &[DVector<C64>], z: &DVector<C64>, tolerance: f64) -> bool {
    known
        .iter()
        .any(|k| norm(&(k - z)) <= tolerance * norm(z).max(1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    /// $x^5 = p$ written quadratic: $y_1 = x^2$, $y_2 = y_1^2$, $x y_2 = p$; five roots for
    /// $p \ne 0$.
    struct Quintic;

    impl QuadraticFamily for Quintic {
        fn unknowns(&self) -> usize {
            3
        }
        fn residual(&self, z: &[C64], p: &[C64], f: &mut [C64]) {
            f[0] = z[1] - z[0] * z[0];
            f[1] = z[2] - z[1] * z[1];
            f[2] = z[0] * z[2] - p[0];
        }
    }

    /// A circle and a line: $x^2 + y^2 = r^2$, $a x + b y = c$; two solutions.
    struct CircleLine;

    impl QuadraticFamily for CircleLine {
        fn unknowns(&self) -> usize {
            2
        }
        fn residual(&self, z: &[C64], p: &[C64], f: &mut [C64]) {
            let (x, y) = (z[0], z[1]);
            f[0] = x * x + y * y - p[0] * p[0];
            f[1] = p[1] * x + p[2] * y - p[3];
        }
    }

    /// Monodromy finds the five fifth roots of a complex number from one, and tracking them to
    /// $p = 32$ gives $2 e^{2\pi i k/5}$ to 1e-12.
    #[test]
    fn finds_every_root_of_a_quintic_and_tracks_them() {
        let p0 = [C64::new(0.3, 0.7)];
        let x = p0[0].powf(0.2);
        let start = DVector::from_vec(vec![x, x * x, x * x * x * x]);
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let found = monodromy(
            &Quintic,
            &p0,
            start,
            &MonodromySettings::default(),
            &mut rng,
        );
        assert_eq!(found.solutions.len(), 5, "{found:?}");
        assert!(found.stable);
        let target = [C64::new(32.0, 0.0)];
        let mut ends: Vec<C64> = found
            .solutions
            .iter()
            .map(
                |z| match track(&Quintic, z, &p0, &target, &TrackSettings::default()).end {
                    Endpoint::Regular(e) => e[0],
                    other => panic!("{other:?}"),
                },
            )
            .collect();
        ends.sort_by(|a, b| a.arg().total_cmp(&b.arg()));
        for root in &ends {
            let k = (root.arg() / (2.0 * std::f64::consts::PI / 5.0)).round();
            let expected = C64::from_polar(2.0, k * 2.0 * std::f64::consts::PI / 5.0);
            assert!((root - expected).norm() < 1e-12, "{root} vs {expected}");
        }
    }

    /// The same bits on one thread and on two: the monodromy and `track_many` of the quintic
    /// run in rayon pools of each size.
    #[test]
    fn the_same_bits_whatever_the_thread_count() {
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let p0 = [C64::new(0.3, 0.7)];
                let x = p0[0].powf(0.2);
                let start = DVector::from_vec(vec![x, x * x, x * x * x * x]);
                let mut rng = ChaCha8Rng::seed_from_u64(7);
                let settings = MonodromySettings::default();
                let found = monodromy(&Quintic, &p0, start, &settings, &mut rng);
                let target = [C64::new(32.0, 0.0)];
                let paths = track_many(&Quintic, &found.solutions, &p0, &target, &settings.track);
                (found.solutions, paths)
            })
        };
        assert_eq!(run(1), run(2));
    }

    /// The circle and the line: two real intersections at a real target, two complex ones
    /// when the line misses the circle, and a tangent line's double root ends singular.
    #[test]
    fn circle_and_line_real_complex_and_tangent() {
        let p0: Vec<C64> = [0.8, 0.3, -0.6, 0.2]
            .iter()
            .zip([0.4, -0.2, 0.5, 0.1])
            .map(|(&re, im)| C64::new(re, im))
            .collect();
        // A solution of p0: pick x, solve the line for y, then the radius.
        let x = C64::new(0.1, 0.2);
        let y = (p0[3] - p0[1] * x) / p0[2];
        let mut p0 = p0;
        p0[0] = (x * x + y * y).sqrt();
        let start = DVector::from_vec(vec![x, y]);
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let found = monodromy(
            &CircleLine,
            &p0,
            start,
            &MonodromySettings::default(),
            &mut rng,
        );
        assert_eq!(found.solutions.len(), 2);
        let ends = |target: [f64; 4]| -> Vec<Endpoint> {
            let t: Vec<C64> = target.iter().map(|&v| C64::new(v, 0.0)).collect();
            found
                .solutions
                .iter()
                .map(|z| track(&CircleLine, z, &p0, &t, &TrackSettings::default()).end)
                .collect()
        };
        // x² + y² = 1, x = 0.6: (0.6, ±0.8).
        for end in ends([1.0, 1.0, 0.0, 0.6]) {
            let Endpoint::Regular(z) = end else {
                panic!("{end:?}")
            };
            assert!((z[0] - C64::new(0.6, 0.0)).norm() < 1e-12);
            assert!((z[1].re.abs() - 0.8).abs() < 1e-12 && z[1].im.abs() < 1e-12);
        }
        // x = 2 misses the circle: y = ±i√3.
        for end in ends([1.0, 1.0, 0.0, 2.0]) {
            let Endpoint::Regular(z) = end else {
                panic!("{end:?}")
            };
            assert!(z[1].re.abs() < 1e-12 && (z[1].im.abs() - 3f64.sqrt()).abs() < 1e-10);
        }
        // x = 1 is tangent: a double root, not regular.
        for end in ends([1.0, 1.0, 0.0, 1.0]) {
            assert!(!matches!(end, Endpoint::Regular(_)), "{end:?}");
        }
    }
}
