//! activemuscle command line: for now, the chapter's homogeneous curves along the fibres as a table.

use activemuscle::active::{ActiveCurve, Coupling, EnergyLaw, ExplicitLaw, FrozenTangent, ImplicitLaw, Law};
use activemuscle::energy::{EhretBolItskov, GiantesioMusesti};
use activemuscle::uniaxial::along_fibres;
use activemuscle::Muscle;
use std::process::ExitCode;

fn run() -> activemuscle::Result<()> {
    let gm = GiantesioMusesti::paper();
    let curve = ActiveCurve::paper();
    let frozen = Coupling::Frozen(FrozenTangent::Exact);
    let passive = Muscle::passive(gm);
    let ebi = Muscle::passive(EhretBolItskov::paper());
    let implicit = Muscle::new(gm, Law::Implicit(ImplicitLaw::new(gm, curve)), 0.0, frozen)?;
    let explicit = Muscle::new(gm, Law::Explicit(ExplicitLaw::paper()), 0.0, frozen)?;
    let energy = Muscle::new(gm, Law::Energy(EnergyLaw::new(gm, curve)), 0.0, Coupling::Consistent)?;
    println!("# Uniaxial tension along the fibres (Giantesio & Musesti), nominal stress in kPa, d = 0");
    println!(
        "{:>6} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}",
        "lambda", "P_pas", "P_EBI", "P_act", "g_impl", "P_impl", "g_expl", "P_expl", "g_energy", "P_energy"
    );
    for i in 0..=95 {
        let l = 0.65 + 0.01 * i as f64;
        let (pi, pe, pc) = (along_fibres(&implicit, l)?, along_fibres(&explicit, l)?, along_fibres(&energy, l)?);
        println!(
            "{:6.2} {:10.4} {:10.4} {:10.4} {:10.6} {:10.4} {:10.6} {:10.4} {:10.6} {:10.4}",
            l,
            along_fibres(&passive, l)?.stress,
            along_fibres(&ebi, l)?.stress,
            curve.value(l),
            pi.gamma,
            pi.stress,
            pe.gamma,
            pe.stress,
            pc.gamma,
            pc.stress
        );
    }
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
