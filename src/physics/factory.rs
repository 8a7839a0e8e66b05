//! The point model (constitutive law, permeability, remodelling) a scene's `[material]` asks for.

use crate::error::{Error, Result};
use crate::fem::point::PointModel;
use crate::material::{ellipticity, HolmesMow};
use crate::physics::biphasic::Biphasic;
use crate::physics::linear::LinearPoroelastic;
use crate::scene::{HolmesMowSpec, LoadedScene, Material, SolidSpec};

/// The Holmes–Mow solid of a scene: from (µ, ν) by (56), or from its α's.
fn holmes_mow(spec: &HolmesMowSpec) -> Result<HolmesMow> {
    match spec.solid().map_err(Error::Material)? {
        SolidSpec::MuNu { mu, nu } => HolmesMow::from_mu_nu(mu, nu, spec.phi_s),
        SolidSpec::Alpha(a) => HolmesMow::new(spec.phi_s, a[0], a[1], a[2], 1.0),
    }
}

/// A warning for a solid law that loses strong ellipticity under the strains of a compression
/// experiment (`material::ellipticity`, closed form): there the solve stops converging, on
/// every mesh. It names the compression limit (any elastic principal stretch below
/// √(−α1/α2)) and the uniaxial-stress tension limit, where the lateral contraction reaches it.
pub fn ellipticity_warning(scene: &LoadedScene) -> Result<Option<String>> {
    let Material::HolmesMow(spec) = &scene.scene.material else {
        return Ok(None);
    };
    let solid = holmes_mow(spec)?;
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
        spec.nu.map(|n| format!(": nu = {n} > 1/3")).unwrap_or_default(),
    )))
}

/// The scene's point model.
pub fn model_of(scene: &LoadedScene) -> Result<Box<dyn PointModel>> {
    match &scene.scene.material {
        Material::Linear { mu, nu, permeability } => Ok(Box::new(LinearPoroelastic::new(*mu, *nu, *permeability)?)),
        Material::HolmesMow(spec) => {
            let model = Biphasic::try_from(spec).map_err(|e| {
                let msg = match e {
                    Error::Material(m) => m,
                    e => e.to_string(),
                };
                Error::Scene { path: scene.source.clone(), msg: format!("[material] {msg}") }
            })?;
            Ok(Box::new(model))
        }
    }
}

impl TryFrom<&HolmesMowSpec> for Biphasic {
    type Error = Error;

    /// The mixture of a scene's `[material]`: solid, penalty, permeability, densities, gravity
    /// and remodelling, each checked by its law.
    fn try_from(spec: &HolmesMowSpec) -> Result<Biphasic> {
        use crate::material::{CompactionPenalty, Permeability, PermeabilityModel, Remodelling};
        let solid = holmes_mow(spec)?;
        let phi_s = spec.phi_s;
        let penalty =
            spec.penalty.as_ref().map(|p| CompactionPenalty::new(phi_s, p.u0, p.j_cr, p.q, p.r)).transpose()?;
        let model = match spec.permeability_c {
            Some(c) => PermeabilityModel::RemodellingDependent { c },
            None => PermeabilityModel::Isotropic,
        };
        let perm = Permeability::new(spec.k0, phi_s, spec.kappa, spec.m0, model)?;
        let mut mixture = Biphasic::new(solid, penalty, perm, spec.rho_s, spec.rho_f, spec.gravity)?;
        if let Some(r) = &spec.remodelling {
            let law = Remodelling::new(r.lambda_p, r.sigma_y)?;
            mixture = mixture.with_remodelling(law.with_form(r.form).with_integrator(r.integrator));
        }
        Ok(mixture)
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
