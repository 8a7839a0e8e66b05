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
        _ => unreachable!("validated"),
    }
}

/// A warning for a solid law that loses strong ellipticity under the strains of a compression
/// experiment (`material::ellipticity`): there the solve stops converging, on every mesh.
pub fn ellipticity_warning(scene: &LoadedScene) -> Result<Option<String>> {
    let Material::HolmesMow { mu, nu, alpha, phi_s, .. } = &scene.scene.material else {
        return Ok(None);
    };
    let solid = holmes_mow(*mu, *nu, alpha, *phi_s)?;
    Ok(ellipticity::isochoric_compression_limit(&solid, 0.5)?.map(|lam| {
        format!(
            "the Holmes–Mow solid (alpha1 = {:.3} < 0{}) loses strong ellipticity beyond {:.1}% isochoric \
             compression: strains above that localise, and the solve stops converging there on any mesh \
             (docs/studies.md, stability (f))",
            solid.alpha1,
            nu.map(|n| format!(": nu = {n} > 1/3")).unwrap_or_default(),
            100.0 * (1.0 - lam)
        )
    }))
}

/// The scene's point model.
pub fn model_of(scene: &LoadedScene) -> Result<Box<dyn PointModel>> {
    use crate::material::{CompactionPenalty, FlowForm, Integrator, Permeability, PermeabilityModel, Remodelling};
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
                let form = if r.form == "40a" { FlowForm::Spatial } else { FlowForm::Referential };
                let integrator = if r.integrator == "explicit" { Integrator::Explicit } else { Integrator::Implicit };
                let law = Remodelling::new(r.lambda_p, r.sigma_y).map_err(ctx)?;
                model = model.with_remodelling(law.with_form(form).with_integrator(integrator));
            }
            Ok(Box::new(model))
        }
    }
}
