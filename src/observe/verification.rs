//! Exact-solution columns of the verification scenes (Terzaghi, Cryer) for history.csv.

use super::analytic;
use crate::error::{Error, Result};
use crate::io::recorder::ColumnDoc;
use crate::scene::{LoadedScene, Material, Verification};

/// An exact solution as a function of time.
pub(crate) type ExactFn = Box<dyn Fn(f64) -> f64>;

/// An exact-solution column: what the docs say of it, and its value at a time.
pub(crate) struct Exact {
    pub(crate) doc: &'static ColumnDoc,
    pub(crate) value: ExactFn,
}

const P_BOTTOM: ColumnDoc = ColumnDoc::named(
    "p_bottom_exact",
    "–",
    "Terzaghi's exact pressure at the sealed bottom, over the load (`[verification] kind = \"terzaghi\"`)",
);
const SETTLEMENT: ColumnDoc =
    ColumnDoc::named("settlement_exact", "µm", "Terzaghi's exact settlement of the loaded top");
const P_CENTER: ColumnDoc = ColumnDoc::named(
    "p_center_exact",
    "–",
    "Cryer's exact centre pressure, over the load (`[verification] kind = \"cryer\"`)",
);

/// Every exact-solution column, as the docs list them.
pub(crate) const COLUMNS: [&ColumnDoc; 3] = [&P_BOTTOM, &SETTLEMENT, &P_CENTER];

/// Exact-solution columns of a verification scene.
pub(crate) fn exact_columns(scene: &LoadedScene) -> Result<Vec<Exact>> {
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
            Exact {
                doc: &P_BOTTOM,
                value: Box::new(move |t| {
                    if t > 0.0 {
                        analytic::terzaghi_pressure(0.0, t, height, load, &m) / load
                    } else {
                        0.0
                    }
                }),
            },
            Exact {
                doc: &SETTLEMENT,
                value: Box::new(
                    move |t| if t > 0.0 { analytic::terzaghi_settlement(t, height, load, &m) } else { 0.0 },
                ),
            },
        ],
        Verification::Cryer { radius, load: _ } => {
            let series = analytic::CryerSeries::new(nu, 1e-6)?;
            let c = m.consolidation_coefficient();
            vec![Exact {
                doc: &P_CENTER,
                value: Box::new(move |t| if t > 0.0 { series.center_pressure(c * t / (radius * radius)) } else { 0.0 }),
            }]
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every exact column a shipped verification scene writes is one the docs list ([`COLUMNS`]).
    #[test]
    fn the_shipped_verification_scenes_write_listed_columns() {
        let mut seen = 0;
        for (name, _) in crate::scene::BUILTIN {
            let scene = LoadedScene::load(name, &[]).unwrap();
            for e in exact_columns(&scene).unwrap() {
                assert!(COLUMNS.contains(&e.doc), "{name}: {} is not listed", e.doc.name);
                seen += 1;
            }
        }
        assert_eq!(seen, 3, "the terzaghi and cryer scenes' exact columns");
    }
}
