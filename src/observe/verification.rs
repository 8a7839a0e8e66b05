//! Exact-solution columns of the verification scenes (Terzaghi, Cryer) for history.csv.

use super::analytic;
use crate::error::{Error, Result};
use crate::scene::{LoadedScene, Material, Verification};

/// An exact solution as a function of time.
pub type ExactFn = Box<dyn Fn(f64) -> f64>;

/// Exact-solution columns of a verification scene.
pub fn exact_columns(scene: &LoadedScene) -> Result<Vec<(String, ExactFn)>> {
    let Some(v) = &scene.scene.verification else { return Ok(vec![]) };
    let Material::Linear { mu, nu, permeability } = scene.scene.material.clone() else {
        return Err(Error::Scene {
            path: scene.source.clone(),
            msg: "[verification] needs material.model = \"linear\"".into(),
        });
    };
    let m = analytic::Drained::new(mu, nu, permeability)?;
    Ok(match v.clone() {
        Verification::Terzaghi { height, load } => vec![
            (
                "p_bottom_exact".into(),
                Box::new(
                    move |t| if t > 0.0 { analytic::terzaghi_pressure(0.0, t, height, load, &m) / load } else { 0.0 },
                ) as ExactFn,
            ),
            (
                "settlement_exact".into(),
                Box::new(move |t| if t > 0.0 { analytic::terzaghi_settlement(t, height, load, &m) } else { 0.0 }),
            ),
        ],
        Verification::Cryer { radius, load: _ } => {
            let series = analytic::CryerSeries::new(nu, 1e-6)?;
            let c = m.consolidation_coefficient();
            vec![(
                "p_center_exact".into(),
                Box::new(move |t| if t > 0.0 { series.center_pressure(c * t / (radius * radius)) } else { 0.0 })
                    as ExactFn,
            )]
        }
    })
}
