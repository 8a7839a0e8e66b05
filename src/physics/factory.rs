//! The point model (constitutive law, permeability, remodelling) a scene's `[material]` asks for.
//!
//! A skeleton law is registered in [`with_model`], one line per scene variant: the line builds
//! the law from its keys and hands it, with the mixture's keys, to what needs the law (the point
//! model, the ellipticity warning), which is generic over [`SkeletonLaw`].

use crate::error::{Error, Result};
use crate::fem::point::PointModel;
use crate::material::laws::{HolmesMow, NeoHookean};
use crate::material::{CompactionPenalty, Permeability, PermeabilityModel, Remodelling, SkeletonLaw};
use crate::physics::biphasic::Biphasic;
use crate::physics::linear::LinearPoroelastic;
use crate::scene::{LoadedScene, Material, MixtureSpec, SolidSpec};

/// What is done with a scene's model: the linear one, or a mixture around a skeleton law,
/// whichever law it is.
trait WithModel {
    type Out;
    fn linear(self, mu: f64, nu: f64, permeability: f64) -> Result<Self::Out>;
    fn mixture<L: SkeletonLaw>(self, law: L, spec: &MixtureSpec) -> Result<Self::Out>;
}

/// The registry of models: `w` applied to the scene's `[material]`. A skeleton law is one line
/// here, which builds the law from its keys.
fn with_model<W: WithModel>(material: &Material, w: W) -> Result<W::Out> {
    match material {
        Material::Linear { mu, nu, permeability } => w.linear(*mu, *nu, *permeability),
        Material::HolmesMow(spec) => w.mixture(holmes_mow(spec)?, spec),
        Material::NeoHookean(spec) => w.mixture(neo_hookean(spec)?, spec),
    }
}

/// The Holmes–Mow solid of a scene: from (µ, ν) by (56), or from its α's.
fn holmes_mow(spec: &MixtureSpec) -> Result<HolmesMow> {
    match spec.solid().map_err(Error::Material)? {
        SolidSpec::MuNu { mu, nu } => HolmesMow::from_mu_nu(mu, nu, spec.phi_s),
        SolidSpec::Alpha(a) => HolmesMow::new(spec.phi_s, a[0], a[1], a[2], 1.0),
    }
}

/// The neo-Hookean solid of a scene, from (µ, ν); `alpha` is refused by the scene's checks.
fn neo_hookean(spec: &MixtureSpec) -> Result<NeoHookean> {
    match spec.solid().map_err(Error::Material)? {
        SolidSpec::MuNu { mu, nu } => NeoHookean::from_mu_nu(mu, nu, spec.phi_s),
        SolidSpec::Alpha(_) => Err(Error::Material("neo_hookean: `alpha` is a Holmes–Mow key".into())),
    }
}

/// A warning for a solid law that loses strong ellipticity under the strains of a compression
/// experiment (closed form, [`SkeletonLaw::ellipticity_limit`]): there the solve stops
/// converging, on every mesh. It names the compression limit (any elastic principal stretch
/// below it) and the uniaxial-stress tension limit, where the lateral contraction reaches it.
pub(crate) fn ellipticity_warning(scene: &LoadedScene) -> Result<Option<String>> {
    with_model(&scene.scene.material, Warning)
}

struct Warning;

impl WithModel for Warning {
    type Out = Option<String>;

    /// Linear elasticity is elliptic for every admissible ν.
    fn linear(self, _mu: f64, _nu: f64, _permeability: f64) -> Result<Option<String>> {
        Ok(None)
    }

    fn mixture<L: SkeletonLaw>(self, law: L, spec: &MixtureSpec) -> Result<Option<String>> {
        let Some(limit) = law.ellipticity_limit(0.5)? else {
            return Ok(None);
        };
        let tension = limit
            .uniaxial_tension
            .map(|t| format!("; {:.1}% stretch in uniaxial-stress tension", 100.0 * (t - 1.0)))
            .unwrap_or_default();
        let (lam, pct) = (limit.stretch, 100.0 * (1.0 - limit.stretch));
        Ok(Some(format!(
            "the {} ({}{}) loses strong ellipticity beyond {pct:.1}% isochoric \
             compression, and wherever an elastic principal stretch falls below {lam:.3} ({pct:.1}% \
             compression in uniaxial strain or stress too{tension}): strains above that localise, and the \
             solve stops converging there on any mesh (docs/studies.md, stability (f))",
            limit.law,
            limit.cause,
            spec.nu.map(|n| format!(": nu = {n} > 1/3")).unwrap_or_default(),
        )))
    }
}

/// The scene's point model (an error in its `[material]` names the scene).
pub(crate) fn model_of(scene: &LoadedScene) -> Result<Box<dyn PointModel>> {
    with_model(&scene.scene.material, Model).map_err(|e| {
        let msg = match e {
            Error::Material(m) => m,
            e => e.to_string(),
        };
        Error::Scene { path: scene.source.clone(), msg: format!("[material] {msg}") }
    })
}

struct Model;

impl WithModel for Model {
    type Out = Box<dyn PointModel>;

    fn linear(self, mu: f64, nu: f64, permeability: f64) -> Result<Box<dyn PointModel>> {
        Ok(Box::new(LinearPoroelastic::new(mu, nu, permeability)?))
    }

    fn mixture<L: SkeletonLaw>(self, law: L, spec: &MixtureSpec) -> Result<Box<dyn PointModel>> {
        Ok(Box::new(mixture(law, spec)?))
    }
}

/// The mixture of a scene's `[material]` around its skeleton law: penalty, permeability,
/// densities, gravity and remodelling, each checked by its law.
fn mixture<L: SkeletonLaw>(law: L, spec: &MixtureSpec) -> Result<Biphasic<L>> {
    let phi_s = spec.phi_s;
    let penalty = spec.penalty.as_ref().map(|p| CompactionPenalty::new(phi_s, p.u0, p.j_cr, p.q, p.r)).transpose()?;
    let model = match spec.permeability_c {
        Some(c) => PermeabilityModel::RemodellingDependent { c },
        None => PermeabilityModel::Isotropic,
    };
    let perm = Permeability::new(spec.k0, phi_s, spec.kappa, spec.m0, model)?;
    let mut mixture = Biphasic::new(law, penalty, perm, spec.rho_s, spec.rho_f, spec.gravity)?;
    if let Some(r) = &spec.remodelling {
        let law = Remodelling::new(r.lambda_p, r.sigma_y)?;
        mixture = mixture.with_remodelling(law.with_form(r.form).with_integrator(r.integrator));
    }
    Ok(mixture)
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
