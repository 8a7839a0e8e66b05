//! A whole scene's checks: each section's in turn, then the unit slips ([`plausible`]) and the
//! `[petsc]` values.

use super::plausible;
use super::sections::Scene;

impl Scene {
    /// Checks ranges and consistency, section by section; the message names the key and value.
    /// What is allowed but likely a mistake is a note in `notes`.
    pub(super) fn validate(&self, notes: &mut Vec<String>) -> Result<(), String> {
        self.mesh.validate()?;
        self.material.validate()?;
        for (i, bc) in self.bc.iter().enumerate() {
            bc.validate(i)?;
        }
        if let Some(init) = &self.initial {
            init.validate()?;
        }
        self.output.validate()?;
        self.time.validate(&self.output.fields_at, self.plates.is_some())?;
        for p in &self.probe {
            p.validate()?;
        }
        if let Some(p) = &self.plates {
            p.validate(self.time.t_end, notes)?;
        }
        super::tools::validate(&self.tools, self.mesh.geometry, notes)?;
        if let Some(v) = &self.verification {
            v.validate()?;
        }
        if let Some(sf) = &self.surface {
            sf.validate(self.plates.is_some())?;
        }
        if let Some(m) = &self.medium {
            m.validate(self.material.mixture(), &self.bc, &self.tools)?;
        }
        if let Some(d) = &self.drainage {
            d.validate(self.plates.is_some())?;
        }
        self.fem.validate(self.mesh.geometry)?;
        plausible::check(self, notes)?;
        self.validate_petsc()
    }

    /// [petsc]: scalar values only.
    fn validate_petsc(&self) -> Result<(), String> {
        for (k, v) in &self.petsc {
            if matches!(v, toml::Value::Array(_) | toml::Value::Table(_)) {
                return Err(format!("[petsc] {k}: values must be strings, numbers or booleans"));
            }
        }
        Ok(())
    }
}
