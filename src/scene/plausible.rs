//! Unit slips: a value inside its key's valid range that no aggregate or experiment has in the
//! solver's unit (kPa, µm, s, µm⁴/(nN s), (kPa s)⁻¹, kg/m³, m/s²), most likely written in another
//! (a modulus in Pa, a time in ms, a permeability in m⁴/(N s)). Far outside what is measured it
//! is refused; outside the usual values, a note. Either names the unit that puts the value among
//! the usual ones, when one does. (The radius and the surface tension have their own checks, in
//! `mesh` and `surface`.)

use super::material::Material;
use super::sections::Scene;
use super::time::LONGEST_USUAL_TIME;

/// The plausible values of a quantity in the solver's unit, and the slips that put a value
/// outside them.
struct Quantity {
    unit: &'static str,
    /// Outside: refused. Zero is not checked (it switches a term off where a key allows it).
    hard: (f64, f64),
    /// Outside (inside `hard`): a note.
    usual: (f64, f64),
    /// What is measured, for the message.
    measured: &'static str,
    /// Other units a value may have been written in: (name, its size in the solver's unit).
    slips: &'static [(&'static str, f64)],
}

const MODULUS: Quantity = Quantity {
    unit: "kPa",
    hard: (1e-4, 1e4),
    usual: (0.01, 1000.0),
    measured: "tissue moduli lie around 0.01–1000 kPa (aggregates 0.1–10 kPa)",
    slips: &[("Pa", 1e-3), ("MPa", 1e3)],
};
const PERMEABILITY: Quantity = Quantity {
    unit: "µm⁴/(nN s)",
    hard: (1e-9, 1e6),
    usual: (1e-2, 1e3),
    measured: "tissue permeabilities lie around 0.01–1000 µm⁴/(nN s) (cartilage 0.1–1; the paper's aggregate 3.77)",
    slips: &[("m⁴/(N s)", 1e15), ("mm⁴/(N s)", 1e3)],
};
/// The plates' permeability k_β (its conductance is k_β / thickness): only the refusal.
const PLATE_PERMEABILITY: Quantity = Quantity {
    unit: "µm⁴/(nN s)",
    hard: (1e-12, 1e6),
    usual: (1e-12, 1e6),
    measured: "k_β of porous plates lies far inside 1e-12–1e6 µm⁴/(nN s) (the paper's 3.7729e-4)",
    slips: &[("m⁴/(N s)", 1e15)],
};
const FLOW_RATE: Quantity = Quantity {
    unit: "(kPa s)⁻¹",
    hard: (1e-9, 1e3),
    usual: (1e-6, 0.5),
    measured:
        "remodelling rates λp lie around 1e-6–0.5 (kPa s)⁻¹ (tissue viscosities 2 kPa s–1 GPa s; the paper's 0.001)",
    slips: &[("(MPa s)⁻¹", 1e-3), ("(Pa s)⁻¹", 1e3)],
};
const TIME: Quantity = Quantity {
    unit: "s",
    hard: (0.0, 1e7),
    usual: (0.0, LONGEST_USUAL_TIME),
    measured: "experiments last seconds to hours",
    slips: &[("ms", 1e-3)],
};
const DENSITY: Quantity = Quantity {
    unit: "kg/m³",
    hard: (10.0, 1e5),
    usual: (500.0, 3000.0),
    measured: "cells and media have about 1000–1100 kg/m³",
    slips: &[("g/cm³", 1e3)],
};
const GRAVITY: Quantity = Quantity {
    unit: "m/s²",
    hard: (0.0, 500.0),
    usual: (0.0, 100.0),
    measured: "g is 9.81 m/s² (a smaller |g| models buoyancy)",
    slips: &[("cm/s²", 1e-2), ("mm/s²", 1e-3)],
};
const THICKNESS: Quantity = Quantity {
    unit: "µm",
    hard: (1e-3, 1e6),
    usual: (0.1, 1e5),
    measured: "plates are µm to cm thick",
    slips: &[("mm", 1e3), ("m", 1e6)],
};

/// Every dimensioned value of `scene` against what is measured: an error for a value far outside,
/// a note in `notes` for an unusual one.
pub(super) fn check(scene: &Scene, notes: &mut Vec<String>) -> Result<(), String> {
    let mut values: Vec<(&str, f64, &Quantity)> = Vec::new();
    if let Material::Linear { mu, permeability, .. } = &scene.material {
        values.extend([("material.mu", *mu, &MODULUS), ("material.permeability", *permeability, &PERMEABILITY)])
    }
    if let Some(m) = scene.material.mixture() {
        let moduli = [
            ("material.mu", m.mu),
            ("material.drained_shear_modulus", m.drained_shear_modulus),
            ("material.drained_youngs_modulus", m.drained_youngs_modulus),
            ("material.alpha[0]", m.alpha.map(|a| a[0])),
            ("material.penalty.u0", m.penalty.as_ref().map(|p| p.u0)),
        ];
        values.extend(moduli.iter().filter_map(|(k, v)| v.map(|v| (*k, v, &MODULUS))));
        values.push(("material.k0", m.k0, &PERMEABILITY));
        if let Some(r) = &m.remodelling {
            values.push(("material.remodelling.lambda_p", r.lambda_p, &FLOW_RATE));
            values.push(("material.remodelling.sigma_y", r.sigma_y, &MODULUS));
        }
        values.push(("material.rho_s", m.rho_s, &DENSITY));
        values.push(("material.rho_f", m.rho_f, &DENSITY));
        values.push(("|material.gravity|", m.gravity_magnitude(), &GRAVITY));
    }
    values.push(("time.t_end", scene.time.t_end, &TIME));
    if let Some(p) = &scene.plates {
        if let Some(rows) = &p.table {
            values.push(("plates.table's last time", rows[rows.len() - 1][0], &TIME));
        } else {
            for (k, v) in [("plates.ramp", p.ramp), ("plates.hold", p.hold), ("plates.release", p.release)] {
                values.extend(v.map(|v| (k, v, &TIME)));
            }
        }
        values.extend(p.permeability.map(|k| ("plates.permeability", k, &PLATE_PERMEABILITY)));
        values.extend(p.thickness.map(|l| ("plates.thickness", l, &THICKNESS)));
        check_forces(scene, p)?;
    }
    if let Some(m) = &scene.medium {
        check_suctions(scene, m)?;
    }
    for (key, v, q) in values {
        if let Some(note) = judge(key, v, q)? {
            notes.push(note);
        }
    }
    Ok(())
}

/// The upper plate's forces (µN) against the body's scale E R² (E: the first modulus given):
/// beyond 10³ E R² or below 10⁻⁶ E R² the force is refused as written in another unit.
fn check_forces(scene: &Scene, p: &super::plates::PlatesSpec) -> Result<(), String> {
    let (Some(e), Some(rows)) = (modulus(scene), &p.upper) else { return Ok(()) };
    // E R² in nN (kPa µm²), as µN.
    let scale = e * p.radius() * p.radius() * 1e-3;
    for (i, f) in rows.iter().enumerate().filter_map(|(i, r)| r.force.map(|f| (i + 1, f))) {
        if f > 1e3 * scale || f < 1e-6 * scale {
            return Err(format!(
                "plates.upper row {i}: force = {} µN is {} the plausible {}–{} µN for a body of modulus {e} kPa \
                 and radius {} µm (10⁻⁶–10³ E R²): forces are in µN (nN? divide by 1000; mN? multiply by 1000)",
                crate::io::fmt_real(f),
                if f > scale { "above" } else { "below" },
                crate::io::fmt_significant(1e-6 * scale, 3),
                crate::io::fmt_significant(1e3 * scale, 3),
                p.radius()
            ));
        }
    }
    Ok(())
}

/// The body's modulus for the scale checks: the first modulus given (kPa).
fn modulus(scene: &Scene) -> Option<f64> {
    match &scene.material {
        Material::Linear { mu, .. } => Some(*mu),
        _ => scene.material.mixture().and_then(|m| m.mu.or(m.drained_shear_modulus).or(m.drained_youngs_modulus)),
    }
}

/// The suctions (kPa) against the body's modulus E: above 10 E an aggregate would be swallowed
/// whole; such a value is a suction in Pa written as kPa.
fn check_suctions(scene: &Scene, m: &super::medium::MediumSpec) -> Result<(), String> {
    let Some(e) = modulus(scene) else { return Ok(()) };
    for (i, s) in m.suction.iter().enumerate() {
        if let Some((j, row)) = s.table.iter().enumerate().find(|(_, r)| r.dp.abs() > 10.0 * e) {
            return Err(format!(
                "medium.suction #{} table row {}: dp = {} kPa is above 10 E = {} kPa for a body of modulus {e} kPa: \
                 Pa given as kPa? (divide by 1000)",
                i + 1,
                j + 1,
                crate::io::fmt_real(row.dp),
                crate::io::fmt_real(10.0 * e)
            ));
        }
    }
    Ok(())
}

/// Err when `v` is far outside what is measured, Some(note) when unusual, None when usual or 0.
fn judge(key: &str, v: f64, q: &Quantity) -> Result<Option<String>, String> {
    let inside = |(lo, hi): (f64, f64)| v >= lo && v <= hi;
    if v == 0.0 || !v.is_finite() || inside(q.usual) {
        return Ok(None);
    }
    let shown = crate::io::fmt_real(v);
    let slip = q
        .slips
        .iter()
        .find(|(_, k)| inside((q.usual.0 / k, q.usual.1 / k)))
        .map(|(u, k)| {
            format!(
                ": {shown} looks like {u} ({shown} {u} = {} {}; write that)",
                crate::io::fmt_significant(v * k, 6),
                q.unit
            )
        })
        .unwrap_or_default();
    let said = format!("{key} = {shown} {}: {}{slip}", q.unit, q.measured);
    if inside(q.hard) {
        Ok(Some(format!("{said} — unusual; check the unit")))
    } else {
        Err(format!("{said} — refused as a unit mistake"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::LoadedScene;

    fn load(set: &[&str]) -> Result<LoadedScene, String> {
        let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
        LoadedScene::load("reference_axi", &set).map_err(|e| e.to_string())
    }

    #[test]
    fn a_modulus_in_pa_is_refused_with_its_value_in_kpa() {
        let e = load(&["material.drained_youngs_modulus=28800"]).unwrap_err();
        assert!(e.contains("material.drained_youngs_modulus = 28800 kPa"), "{e}");
        assert!(e.contains("28800 looks like Pa (28800 Pa = 28.8 kPa; write that)"), "{e}");
        // 5000 Pa written as kPa: 5 MPa, a note (cartilage is that stiff), naming Pa.
        let s = load(&["material.drained_youngs_modulus=5000"]).unwrap();
        assert!(s.notes.iter().any(|n| n.contains("5000 looks like Pa (5000 Pa = 5 kPa")), "{:?}", s.notes);
        // MPa written: 0.0012 for 1.2 kPa.
        let s = load(&["material.drained_youngs_modulus=0.0012"]).unwrap();
        assert!(s.notes.iter().any(|n| n.contains("looks like MPa (0.0012 MPa = 1.2 kPa")), "{:?}", s.notes);
    }

    #[test]
    fn the_shipped_values_are_usual() {
        for (name, _) in crate::scene::BUILTIN {
            let s = LoadedScene::load(name, &[]).unwrap();
            assert!(!s.notes.iter().any(|n| n.contains("check the unit")), "{name}: {:?}", s.notes);
        }
    }

    #[test]
    fn permeability_rate_density_gravity_and_times_name_their_slips() {
        let e = load(&["material.k0=3.7729e-15"]).unwrap_err();
        assert!(e.contains("looks like m⁴/(N s) (3.7729e-15 m⁴/(N s) = 3.7729 µm⁴/(nN s)"), "{e}");
        let s = load(&["material.k0=3.7729e-3"]).unwrap();
        assert!(s.notes.iter().any(|n| n.contains("looks like mm⁴/(N s)")), "{:?}", s.notes);
        let s = load(&["material.remodelling={ lambda_p = 1.0, sigma_y = 2.0 }"]).unwrap();
        assert!(
            s.notes.iter().any(|n| n.contains("looks like (MPa s)⁻¹ (1 (MPa s)⁻¹ = 0.001 (kPa s)⁻¹")),
            "{:?}",
            s.notes
        );
        let e = load(&["material.rho_s=1.05"]).unwrap_err();
        assert!(e.contains("looks like g/cm³ (1.05 g/cm³ = 1050 kg/m³"), "{e}");
        let e = load(&["material.gravity=[0.0, 0.0, -981.0]"]).unwrap_err();
        assert!(e.contains("looks like cm/s² (981 cm/s² = 9.81 m/s²"), "{e}");
        let s = load(&["time.t_end=400000", "plates.hold=350000"]).unwrap();
        assert!(
            s.notes.iter().any(|n| n.contains("plates.hold = 350000 s") && n.contains("looks like ms")),
            "{:?}",
            s.notes
        );
        let e = load(&["time.t_end=4e7"]).unwrap_err();
        assert!(e.contains("time.t_end = 40000000 s") && e.contains("refused"), "{e}");
    }

    #[test]
    fn zero_switches_off_and_is_not_judged() {
        assert!(judge("x", 0.0, &MODULUS).unwrap().is_none());
        assert!(judge("x", 2.0, &MODULUS).unwrap().is_none());
        assert!(judge("x", 1e-5, &MODULUS).is_err());
    }
}
