//! OpenSim's `lmdif_C` — its C translation of MINPACK's `lmdif` (Levenberg–Marquardt with a
//! forward-difference Jacobian), with `lmpar`, `qrfac`, `qrsolv` and `enorm` — for the one
//! unknown and one residual `WrapTorus` solves, with its settings: start 0, ftol = xtol = 1e-4,
//! gtol = 0, at most 500 evaluations, `mode` 1 (scaled by the Jacobian's column norm), initial
//! step bound factor 0.2. OpenSim's changes to MINPACK are kept: a fixed difference step of
//! 1e-5, a first step bound within 1e-4 of zero replaced by the factor, `MACHEP` = 1.2e-16. The
//! iteration stops far from convergence, so every operation is MINPACK's, in its order, with
//! the 1×1 matrices written out.

/// `ftol`: relative reduction of the sum of squares below which it stops.
const FTOL: f64 = 1e-4;
/// `xtol`: relative step bound below which it stops.
const XTOL: f64 = 1e-4;
/// `gtol`.
const GTOL: f64 = 0.0;
/// `maxfev`.
const MAX_EVALUATIONS: usize = 500;
/// `factor`: the first step bound relative to the scaled unknown.
const FACTOR: f64 = 0.2;
/// `fdjac2`'s difference step (OpenSim's constant `eps`).
const STEP: f64 = 1e-5;
/// OpenSim's `MACHEP`.
const MACHEP: f64 = 1.2e-16;
/// OpenSim's `DWARF`.
const DWARF: f64 = 1.0e-38;
/// `enorm`'s bounds of the components it squares directly.
const RDWARF: f64 = 3.834e-20;
const RGIANT: f64 = 1.304e19;

/// `enorm` of one component: |x|, as the square root of its square in the intermediate range.
fn enorm(x: f64) -> f64 {
    let xabs = x.abs();
    if xabs > RDWARF && xabs < RGIANT { (xabs * xabs).sqrt() } else { xabs }
}

/// `dmax1`.
fn dmax1(a: f64, b: f64) -> f64 {
    if a >= b { a } else { b }
}

/// `dmin1`.
fn dmin1(a: f64, b: f64) -> f64 {
    if a <= b { a } else { b }
}

/// The 1×1 QR factorisation (`qrfac`) of the Jacobian and what `lmdif` derives from it.
struct Factorisation {
    /// R (`rdiag` = −‖column‖, the sign of the Householder reflection).
    r: f64,
    /// The column's norm (`acnorm`).
    norm: f64,
    /// First component of Qᵀ f (`qtf`).
    qtf: f64,
}

impl Factorisation {
    fn new(jacobian: f64, fvec: f64) -> Factorisation {
        let norm = enorm(jacobian);
        let mut ajnorm = enorm(jacobian);
        let mut householder = jacobian;
        if ajnorm != 0.0 {
            if householder < 0.0 {
                ajnorm = -ajnorm;
            }
            householder /= ajnorm;
            householder += 1.0;
        }
        let mut qtf = fvec;
        if householder != 0.0 {
            let temp = -(0.0 + householder * qtf) / householder;
            qtf += householder * temp;
        }
        Factorisation { r: -ajnorm, norm, qtf }
    }

    /// The scaled gradient's norm (`gnorm`).
    fn gradient_norm(&self, fnorm: f64) -> f64 {
        if fnorm == 0.0 || self.norm == 0.0 {
            return 0.0;
        }
        dmax1(0.0, ((0.0 + self.r * (self.qtf / fnorm)) / self.norm).abs())
    }
}

/// The iteration's state between steps.
struct State {
    x: f64,
    fvec: f64,
    fnorm: f64,
    par: f64,
    delta: f64,
    xnorm: f64,
    diag: f64,
    evaluations: usize,
    iteration: usize,
}

/// `lmdif_C` from 0 on the residual `f`: the unknown where it stops.
pub(super) fn solve(f: impl Fn(f64) -> f64) -> f64 {
    let fvec = f(0.0);
    let mut state = State { x: 0.0, fvec, fnorm: enorm(fvec), par: 0.0, delta: 0.0, xnorm: 0.0, diag: 0.0, evaluations: 1, iteration: 1 };
    loop {
        let factorisation = Factorisation::new((f(state.x + STEP) - state.fvec) / STEP, state.fvec);
        if state.iteration == 1 {
            state.diag = if factorisation.norm == 0.0 { 1.0 } else { factorisation.norm };
            state.xnorm = enorm(state.diag * state.x);
            state.delta = FACTOR * state.xnorm;
            if state.delta.abs() <= 1e-4 {
                state.delta = FACTOR;
            }
        }
        let gnorm = factorisation.gradient_norm(state.fnorm);
        if gnorm <= GTOL {
            return state.x;
        }
        state.diag = dmax1(state.diag, factorisation.norm);
        loop {
            match state.step(&f, &factorisation, gnorm) {
                Step::Stop => return state.x,
                Step::Accepted => break,
                Step::Rejected => {}
            }
        }
    }
}

/// How an inner step ended.
enum Step {
    Stop,
    Accepted,
    Rejected,
}

impl State {
    /// One inner step of `lmdif`: the Levenberg–Marquardt step within the bound, the ratio of
    /// actual to predicted reduction, the bound's update, the acceptance and the stopping tests.
    fn step(&mut self, f: &impl Fn(f64) -> f64, factorisation: &Factorisation, gnorm: f64) -> Step {
        let (solution, par) = lmpar(factorisation.r, self.diag, factorisation.qtf, self.delta, self.par);
        self.par = par;
        let step = -solution;
        let trial = self.x + step;
        let pnorm = enorm(self.diag * step);
        if self.iteration == 1 {
            self.delta = dmin1(self.delta, pnorm);
        }
        let ftrial = f(trial);
        self.evaluations += 1;
        let fnorm1 = enorm(ftrial);
        let mut actred = -1.0;
        if 0.1 * fnorm1 < self.fnorm {
            let temp = fnorm1 / self.fnorm;
            actred = 1.0 - temp * temp;
        }
        let temp1 = enorm(0.0 + factorisation.r * step) / self.fnorm;
        let temp2 = (self.par.sqrt() * pnorm) / self.fnorm;
        let prered = temp1 * temp1 + (temp2 * temp2) / 0.5;
        let dirder = -(temp1 * temp1 + temp2 * temp2);
        let ratio = if prered != 0.0 { actred / prered } else { 0.0 };
        self.update_bound(ratio, actred, dirder, pnorm, fnorm1);
        if ratio >= 1e-4 {
            self.x = trial;
            self.xnorm = enorm(self.diag * self.x);
            self.fvec = ftrial;
            self.fnorm = fnorm1;
            self.iteration += 1;
        }
        let reduced = actred.abs() <= FTOL && prered <= FTOL && 0.5 * ratio <= 1.0;
        let stringent = actred.abs() <= MACHEP && prered <= MACHEP && 0.5 * ratio <= 1.0;
        if reduced || self.delta <= XTOL * self.xnorm || self.evaluations >= MAX_EVALUATIONS || stringent || self.delta <= MACHEP * self.xnorm || gnorm <= MACHEP {
            Step::Stop
        } else if ratio < 1e-4 {
            Step::Rejected
        } else {
            Step::Accepted
        }
    }

    /// The step bound and the Levenberg–Marquardt parameter after a step.
    fn update_bound(&mut self, ratio: f64, actred: f64, dirder: f64, pnorm: f64, fnorm1: f64) {
        if ratio <= 0.25 {
            let mut temp = if actred >= 0.0 { 0.5 } else { 0.5 * dirder / (dirder + 0.5 * actred) };
            if 0.1 * fnorm1 >= self.fnorm || temp < 0.1 {
                temp = 0.1;
            }
            self.delta = temp * dmin1(self.delta, pnorm / 0.1);
            self.par /= temp;
        } else if self.par == 0.0 || ratio >= 0.75 {
            self.delta = pnorm / 0.5;
            self.par *= 0.5;
        }
    }
}

/// `lmpar`: the Levenberg–Marquardt parameter `par` (from the estimate `par`) for which the
/// step x solving r·x = qtb, √par·diag·x = 0 has |diag·x| within 10 % of `delta` (at most 10
/// tries), and that step: (x, par).
fn lmpar(r: f64, diag: f64, qtb: f64, delta: f64, par: f64) -> (f64, f64) {
    let nonsingular = r != 0.0;
    let mut x = if nonsingular { qtb / r } else { 0.0 };
    let mut dxnorm = enorm(diag * x);
    let mut fp = dxnorm - delta;
    if fp <= 0.1 * delta {
        return (x, 0.0);
    }
    // Bounds on the zero of |diag·x(par)| − delta: below, the Newton step's (none when r is
    // singular); above, the gradient's.
    let mut parl = 0.0;
    if nonsingular {
        let temp = enorm((diag * ((diag * x) / dxnorm) - 0.0) / r);
        parl = ((fp / delta) / temp) / temp;
    }
    let (mut paru, gnorm) = upper_bound(r, diag, qtb, delta);
    let mut par = dmin1(dmax1(par, parl), paru);
    if par == 0.0 {
        par = gnorm / dxnorm;
    }
    for iteration in 1.. {
        if par == 0.0 {
            par = dmax1(DWARF, 0.001 * paru);
        }
        let sdiag;
        (x, sdiag) = qrsolv(r, par.sqrt() * diag, qtb);
        dxnorm = enorm(diag * x);
        let previous = fp;
        fp = dxnorm - delta;
        if fp.abs() <= 0.1 * delta || (parl == 0.0 && fp <= previous && previous < 0.0) || iteration == 10 {
            break;
        }
        let temp = enorm(diag * ((diag * x) / dxnorm) / sdiag);
        let parc = ((fp / delta) / temp) / temp;
        if fp > 0.0 {
            parl = dmax1(parl, par);
        }
        if fp < 0.0 {
            paru = dmin1(paru, par);
        }
        par = dmax1(parl, par + parc);
    }
    (x, par)
}

/// `lmpar`'s upper bound `paru` on the parameter, and the scaled gradient's norm.
fn upper_bound(r: f64, diag: f64, qtb: f64, delta: f64) -> (f64, f64) {
    let gnorm = enorm((0.0 + r * qtb) / diag);
    let paru = gnorm / delta;
    (if paru == 0.0 { DWARF / dmin1(delta, 0.1) } else { paru }, gnorm)
}

/// `qrsolv`: x solving r·x = qtb, d·x = 0 in the least-squares sense, by a Givens rotation
/// eliminating d; (x, the rotated diagonal `sdiag`).
fn qrsolv(r: f64, d: f64, qtb: f64) -> (f64, f64) {
    let mut wa = qtb;
    let mut sdiag = r;
    if d != 0.0 {
        let (cos, sin) = if r.abs() < d.abs() {
            let cotan = r / d;
            let sin = 0.5 / (0.25 + 0.25 * cotan * cotan).sqrt();
            (sin * cotan, sin)
        } else {
            let tan = d / r;
            let cos = 0.5 / (0.25 + 0.25 * tan * tan).sqrt();
            (cos, cos * tan)
        };
        sdiag = cos * r + sin * d;
        wa = cos * wa + sin * 0.0;
    }
    let x = if sdiag == 0.0 { 0.0 } else { (wa - 0.0) / sdiag };
    (x, sdiag)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A smooth residual with a root: the iteration stops near it, within its loose tolerances.
    #[test]
    fn finds_a_root_within_its_tolerances() {
        let x = solve(|x| 2.0 * (x - 0.3) + 0.5 * (x - 0.3).powi(3));
        assert!((x - 0.3).abs() < 1e-3, "{x}");
        // Its residual's norm is reduced far below the start's.
        assert!((2.0 * (x - 0.3) + 0.5 * (x - 0.3).powi(3)).abs() < 1e-3 * 0.6135);
    }

    #[test]
    fn one_component_norms_are_absolute_values() {
        for x in [0.0, -1e-25, 3.0, -2.5e-7, 1e20, f64::MIN_POSITIVE] {
            assert_eq!(enorm(x), x.abs());
        }
    }
}
