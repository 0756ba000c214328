//! The benchmark's hand-derived closed form (benches/closed_form) against the crate's fast AD
//! route (`response::active_response`, invariants of C) and the oracle (`oracle::full_response`,
//! dual numbers over F's nine entries and γ by matrix products): stress, tangent and dP/dγ to
//! 1e-12 relative (max-norm of the difference over the max-norm of the reference) at random F
//! near the identity, random unit m and γ ∈ [0, 0.4]. Checks the yardstick and, independently of
//! the invariant calculus, the AD.

#[path = "../../benches/closed_form/mod.rs"]
mod hand_derived;

use activemuscle::energy::GiantesioMusesti;
use activemuscle::invariants::{axial_fibre, axisymmetric_f, Kinematics, AXISYMMETRIC, FULL};
use activemuscle::oracle::full_response;
use activemuscle::response::{active_response, Order};
use hand_derived::ClosedForm;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

const TOL: f64 = 1e-12;
const SAMPLES: usize = 100;

fn rel<const R: usize, const C: usize>(a: &SMatrix<f64, R, C>, b: &SMatrix<f64, R, C>) -> f64 {
    (a - b).amax() / b.amax()
}

fn closed() -> ClosedForm {
    let w = GiantesioMusesti::paper();
    ClosedForm::new(w.mu(), w.alpha(), w.w0())
}

fn random_f(rng: &mut StdRng) -> Matrix3<f64> {
    loop {
        let f = Matrix3::from_fn(|i, j| {
            let one = if i == j { 1.0 } else { 0.0 };
            one + rng.random_range(-0.3..=0.3)
        });
        if f.determinant() > 0.0 {
            return f;
        }
    }
}

fn random_unit(rng: &mut StdRng) -> Vector3<f64> {
    loop {
        let v = Vector3::from_fn(|_, _| rng.random_range(-1.0..=1.0));
        let n = v.norm();
        if n > 0.2 && n <= 1.0 {
            return v / n;
        }
    }
}

/// Largest relative differences seen, per quantity: [energy, stress, tangent, dP/dγ].
#[derive(Default, Debug)]
struct Worst([f64; 4]);

impl Worst {
    fn show(&self) -> String {
        let v: Vec<String> = self.0.iter().map(|x| format!("{x:.2e}")).collect();
        format!("[{}]", v.join(", "))
    }

    fn see(&mut self, what: &str, k: usize, v: f64, sample: usize) {
        assert!(
            v <= TOL,
            "{what}: relative difference {v:e} > {TOL:e} at sample {sample}"
        );
        self.0[k] = self.0[k].max(v);
    }
}

#[test]
fn full_closed_form_matches_fast_ad_and_oracle() {
    let energy = GiantesioMusesti::paper();
    let cf = closed();
    let mut rng = StdRng::seed_from_u64(0x5eed_0001);
    let (mut vs_ad, mut vs_oracle, mut ad_vs_oracle) =
        (Worst::default(), Worst::default(), Worst::default());
    for n in 0..SAMPLES {
        let f = random_f(&mut rng);
        let m = random_unit(&mut rng);
        let gamma = rng.random_range(0.0..=0.4);
        let c = cf.full(&f, &m, gamma).expect("det F > 0");
        let kin = Kinematics::new(&f, &m).unwrap();
        let ad = active_response(&energy, &kin, gamma, Order::Tangent, &FULL).unwrap();
        let or = full_response(&energy, &f, &m, gamma).unwrap();
        let (ad_p, ad_t, ad_g) = (
            ad.stress.unwrap(),
            ad.tangent.unwrap(),
            ad.dstress_dgamma.unwrap(),
        );

        let e = |a: f64, b: f64| ((a - b) / b).abs();
        vs_ad.see("energy vs AD", 0, e(c.energy, ad.energy), n);
        vs_ad.see("stress vs AD", 1, rel(&c.stress, &ad_p), n);
        vs_ad.see("tangent vs AD", 2, rel(&c.tangent, &ad_t), n);
        vs_ad.see("dP/dgamma vs AD", 3, rel(&c.dstress_dgamma, &ad_g), n);

        vs_oracle.see("energy vs oracle", 0, e(c.energy, or.energy), n);
        vs_oracle.see("stress vs oracle", 1, rel(&c.stress, &or.stress), n);
        vs_oracle.see("tangent vs oracle", 2, rel(&c.tangent, &or.tangent), n);
        vs_oracle.see(
            "dP/dgamma vs oracle",
            3,
            rel(&c.dstress_dgamma, &or.dstress_dgamma),
            n,
        );

        ad_vs_oracle.see("AD energy vs oracle", 0, e(ad.energy, or.energy), n);
        ad_vs_oracle.see("AD stress vs oracle", 1, rel(&ad_p, &or.stress), n);
        ad_vs_oracle.see("AD tangent vs oracle", 2, rel(&ad_t, &or.tangent), n);
        ad_vs_oracle.see(
            "AD dP/dgamma vs oracle",
            3,
            rel(&ad_g, &or.dstress_dgamma),
            n,
        );

        // The tangent is major-symmetric (γ held): the closed form fills it so by construction,
        // the oracle's Hessian must agree.
        assert!(rel(&or.tangent.transpose(), &or.tangent) <= TOL);
    }
    eprintln!("3D, {SAMPLES} samples, max relative difference [energy, P, dP/dF, dP/dγ]:");
    eprintln!("  closed form vs fast AD: {}", vs_ad.show());
    eprintln!("  closed form vs oracle:  {}", vs_oracle.show());
    eprintln!("  fast AD vs oracle:      {}", ad_vs_oracle.show());
}

#[test]
fn axisymmetric_closed_form_matches_fast_ad_and_oracle() {
    let energy = GiantesioMusesti::paper();
    let cf = closed();
    let m = axial_fibre();
    let mut rng = StdRng::seed_from_u64(0x5eed_0002);
    let (mut vs_ad, mut vs_oracle, mut vs_full) =
        (Worst::default(), Worst::default(), Worst::default());
    for n in 0..SAMPLES {
        let f5 = loop {
            let v = SVector::<f64, 5>::from_fn(|i, _| {
                let one = if matches!(i, 0 | 3 | 4) { 1.0 } else { 0.0 };
                one + rng.random_range(-0.3..=0.3)
            });
            if axisymmetric_f(&v).determinant() > 0.0 {
                break v;
            }
        };
        let gamma = rng.random_range(0.0..=0.4);
        let f = axisymmetric_f(&f5);
        let c = cf.axisymmetric(&f5, gamma).expect("det F > 0");
        let kin = Kinematics::new(&f, &m).unwrap();
        let ad = active_response(&energy, &kin, gamma, Order::Tangent, &AXISYMMETRIC).unwrap();
        let (ad_p, ad_t, ad_g) = (
            ad.stress.unwrap(),
            ad.tangent.unwrap(),
            ad.dstress_dgamma.unwrap(),
        );

        // The oracle's 9-entry results restricted to the five axisymmetric entries.
        let or = full_response(&energy, &f, &m, gamma).unwrap();
        let pos = AXISYMMETRIC.index.map(|(k, l)| 3 * k + l);
        let or_p = SVector::<f64, 5>::from_fn(|a, _| or.stress[pos[a]]);
        let or_g = SVector::<f64, 5>::from_fn(|a, _| or.dstress_dgamma[pos[a]]);
        let or_t = SMatrix::<f64, 5, 5>::from_fn(|a, b| or.tangent[(pos[a], pos[b])]);
        // The 3D closed form at the same point, restricted likewise.
        let full = cf.full(&f, &m, gamma).unwrap();
        let fu_p = SVector::<f64, 5>::from_fn(|a, _| full.stress[pos[a]]);
        let fu_g = SVector::<f64, 5>::from_fn(|a, _| full.dstress_dgamma[pos[a]]);
        let fu_t = SMatrix::<f64, 5, 5>::from_fn(|a, b| full.tangent[(pos[a], pos[b])]);

        let e = |a: f64, b: f64| ((a - b) / b).abs();
        vs_ad.see("energy vs AD", 0, e(c.energy, ad.energy), n);
        vs_ad.see("stress vs AD", 1, rel(&c.stress, &ad_p), n);
        vs_ad.see("tangent vs AD", 2, rel(&c.tangent, &ad_t), n);
        vs_ad.see("dP/dgamma vs AD", 3, rel(&c.dstress_dgamma, &ad_g), n);

        vs_oracle.see("energy vs oracle", 0, e(c.energy, or.energy), n);
        vs_oracle.see("stress vs oracle", 1, rel(&c.stress, &or_p), n);
        vs_oracle.see("tangent vs oracle", 2, rel(&c.tangent, &or_t), n);
        vs_oracle.see("dP/dgamma vs oracle", 3, rel(&c.dstress_dgamma, &or_g), n);

        vs_full.see("energy vs 3D closed form", 0, e(c.energy, full.energy), n);
        vs_full.see("stress vs 3D closed form", 1, rel(&c.stress, &fu_p), n);
        vs_full.see("tangent vs 3D closed form", 2, rel(&c.tangent, &fu_t), n);
        vs_full.see(
            "dP/dgamma vs 3D closed form",
            3,
            rel(&c.dstress_dgamma, &fu_g),
            n,
        );
    }
    eprintln!(
        "axisymmetric, {SAMPLES} samples, max relative difference [energy, P, dP/dF, dP/dγ]:"
    );
    eprintln!("  closed form vs fast AD:        {}", vs_ad.show());
    eprintln!("  closed form vs oracle:         {}", vs_oracle.show());
    eprintln!("  closed form vs 3D closed form: {}", vs_full.show());
}

/// The closed form's P is the chapter's eq. (7) (without the pressure), evaluated
/// literally with matrices: P = μ/2 (1−γ) F_e { e^{α(I_e−1)} A − C_e⁻¹ A C_e⁻¹ } F_a⁻¹.
#[test]
fn closed_form_stress_is_the_papers_formula() {
    let w = GiantesioMusesti::paper();
    let cf = closed();
    let mut rng = StdRng::seed_from_u64(0x5eed_0003);
    let mut worst = 0.0_f64;
    for _ in 0..SAMPLES {
        let f = random_f(&mut rng);
        let m = random_unit(&mut rng);
        let gamma: f64 = rng.random_range(0.0..=0.4);
        let mm = m * m.transpose();
        let fa_inv = (Matrix3::identity() - mm * gamma).try_inverse().unwrap();
        let fe = f * fa_inv;
        let ce = fe.transpose() * fe;
        let ce_inv = ce.try_inverse().unwrap();
        let a = Matrix3::identity() * (w.w0() / 3.0) + mm * (1.0 - w.w0());
        let i_e = (a * ce).trace();
        let p = fe
            * ((a * (w.alpha() * (i_e - 1.0)).exp()) - ce_inv * a * ce_inv)
            * fa_inv
            * (0.5 * w.mu() * (1.0 - gamma));
        let p = SVector::<f64, 9>::from_fn(|x, _| p[(x / 3, x % 3)]);
        let c = cf.full(&f, &m, gamma).unwrap();
        let r = rel(&c.stress, &p);
        assert!(r <= TOL, "paper's P vs closed form: {r:e}");
        worst = worst.max(r);
    }
    eprintln!("closed-form P vs eq. (7) by matrices: max relative difference {worst:.2e}");
}
