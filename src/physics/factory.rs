//! The point model (constitutive law, permeability, remodelling) a scene's `[material]` asks for.

use crate::error::{Error, Result};
use crate::fem::point::PointModel;
use crate::material::{ellipticity, HolmesMow};
use crate::physics::biphasic::Biphasic;
use crate::physics::linear::LinearPoroelastic;
use crate::scene::{LoadedScene, Material};

/// The Holmes–Mow solid of a scene: from (µ, ν) by (56), or from its α's.
fn holmes_mow(mu: Option<f64>, nu: Option<f64>, alpha: &Option<[f64; 3]>, phi_s: f64) -> Result<HolmesMow> {
    match (mu, nu, alpha) {
        (Some(mu), Some(nu), _) => HolmesMow::from_mu_nu(mu, nu, phi_s),
        (_, _, Some(a)) => HolmesMow::new(phi_s, a[0], a[1], a[2], 1.0),
        _ => Err(Error::Material("holmes_mow: give `mu` and `nu`, or `alpha` (not both)".into())),
    }
}

/// A warning for a solid law that loses strong ellipticity under the strains of a compression
/// experiment (`material::ellipticity`, closed form): there the solve stops converging, on
/// every mesh. It names the compression limit (any elastic principal stretch below
/// √(−α1/α2)) and the uniaxial-stress tension limit, where the lateral contraction reaches it.
pub fn ellipticity_warning(scene: &LoadedScene) -> Result<Option<String>> {
    let Material::HolmesMow { mu, nu, alpha, phi_s, .. } = &scene.scene.material else {
        return Ok(None);
    };
    let solid = holmes_mow(*mu, *nu, alpha, *phi_s)?;
    let Some(lam) = ellipticity::isochoric_compression_limit(&solid, 0.5)? else {
        return Ok(None);
    };
    let tension = ellipticity::uniaxial_stress_tension_limit(&solid)
        .map(|t| format!("; {:.1}% stretch in uniaxial-stress tension", 100.0 * (t - 1.0)))
        .unwrap_or_default();
    let pct = 100.0 * (1.0 - lam);
    Ok(Some(format!(
        "the Holmes–Mow solid (alpha1 = {:.3} < 0{}) loses strong ellipticity beyond {pct:.1}% isochoric \
         compression, and wherever an elastic principal stretch falls below {lam:.3} ({pct:.1}% \
         compression in uniaxial strain or stress too{tension}): strains above that localise, and the \
         solve stops converging there on any mesh (docs/studies.md, stability (f))",
        solid.alpha1,
        nu.map(|n| format!(": nu = {n} > 1/3")).unwrap_or_default(),
    )))
}

/// The scene's point model.
pub fn model_of(scene: &LoadedScene) -> Result<Box<dyn PointModel>> {
    use crate::material::{CompactionPenalty, Permeability, PermeabilityModel, Remodelling};
    let ctx = |e: Error| {
        let msg = match e {
            Error::Material(m) => m,
            e => e.to_string(),
        };
        Error::Scene { path: scene.source.clone(), msg: format!("[material] {msg}") }
    };
    match &scene.scene.material {
        Material::Linear { mu, nu, permeability } => Ok(Box::new(LinearPoroelastic::new(*mu, *nu, *permeability)?)),
        Material::HolmesMow {
            mu,
            nu,
            alpha,
            phi_s,
            k0,
            kappa,
            m0,
            permeability_c,
            penalty,
            rho_s,
            rho_f,
            gravity,
            remodelling,
            ..
        } => {
            let solid = holmes_mow(*mu, *nu, alpha, *phi_s).map_err(ctx)?;
            let pen = penalty
                .as_ref()
                .map(|p| CompactionPenalty::new(*phi_s, p.u0, p.j_cr, p.q, p.r))
                .transpose()
                .map_err(ctx)?;
            let model = match permeability_c {
                Some(c) => PermeabilityModel::RemodellingDependent { c: *c },
                None => PermeabilityModel::Isotropic,
            };
            let perm = Permeability::new(*k0, *phi_s, *kappa, *m0, model).map_err(ctx)?;
            let mut model = Biphasic::new(solid, pen, perm, *rho_s, *rho_f, *gravity).map_err(ctx)?;
            if let Some(r) = remodelling {
                let law = Remodelling::new(r.lambda_p, r.sigma_y).map_err(ctx)?;
                model = model.with_remodelling(law.with_form(r.form).with_integrator(r.integrator));
            }
            Ok(Box::new(model))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ellipticity_warning_names_the_closed_form_limits() {
        let warning = |nu: &str| {
            let sets = ["material.mu=3".to_string(), format!("material.nu={nu}")];
            ellipticity_warning(&LoadedScene::load("reference", &sets).unwrap()).unwrap()
        };
        // ν = 0.45: λ² = 7/9 (11.8%, stretch 0.882) and uniaxial-stress tension √(11/7) − 1.
        let w = warning("0.45").expect("a warning");
        println!("{w}");
        for part in [
            "alpha1 = -0.636 < 0: nu = 0.45 > 1/3",
            "loses strong ellipticity beyond 11.8% isochoric compression",
            "falls below 0.882",
            "25.4% stretch in uniaxial-stress tension",
        ] {
            assert!(w.contains(part), "{part:?} not in {w:?}");
        }
        // ν = 0.35 loses it only beyond 62% compression: outside a compression experiment.
        assert_eq!(warning("0.35"), None);
        assert_eq!(warning("0.3"), None);
    }
}
