//! `[drainage]`: the surface drainage of a scene without `[plates]` (whose drainage is the
//! plates' keys): which surface drains into the bath, sealed where a tool with
//! `tools.drainage = "sealed"` touches it; its keys and checks (`physics::drainage`).

use super::key::{Key, Section, Unset};
use crate::range::Range;
use serde::{Deserialize, Serialize};

/// The drained surface and its conductance's parameters.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct DrainageSpec {
    /// The boundary group that drains.
    #[serde(default = "default_group")]
    pub(crate) group: String,
    /// γ of the free surface's conductance β_max = γ k0 / h.
    #[serde(default = "default_penalty")]
    pub(crate) penalty: f64,
    /// Gap (µm) over which the surface opens off a sealing tool.
    pub(crate) seal_gap: f64,
}

fn default_group() -> String {
    "surface".into()
}

fn default_penalty() -> f64 {
    100.0
}

impl DrainageSpec {
    /// `plates`: whether the scene has `[plates]`, whose keys set their drainage instead.
    pub(super) fn validate(&self, plates: bool) -> Result<(), String> {
        if plates {
            return Err("[drainage] is for a scene without [plates]: with plates, the surface's drainage is \
                        plates.drainage, plates.drainage_penalty and plates.seal_gap (drop [drainage])"
                .into());
        }
        PENALTY.check(self.penalty)?;
        SEAL_GAP.check(self.seal_gap)
    }
}

const GROUP: Key = Key::new("drainage.group", "", Unset::Value("\"surface\""), "the boundary group that drains");
const PENALTY: Key = Key::new(
    "drainage.penalty",
    "",
    Unset::Value("100.0"),
    "γ of the free-surface drainage conductance β_max = γ k0 / h (a stiff Robin condition, p ≈ p_medium)",
)
.range(Range::POSITIVE)
.enters("numerics.md: Drainage off the tools");
const SEAL_GAP: Key = Key::new(
    "drainage.seal_gap",
    "µm",
    Unset::Required,
    "gap to a sealing tool over which the surface's drainage opens; below the gap of the first node outside \
     the contact edge",
)
.range(Range::POSITIVE)
.enters("numerics.md: Drainage off the tools");

pub(super) const SECTION: Section = Section {
    title: "drainage",
    enters: "numerics.md: Drainage off the tools",
    about: "The drainage of a scene without [plates]: the group drains into the bath (p → p_medium, a stiff \
            Robin condition) except where a sealing tool (tools.drainage = \"sealed\", the default) touches it; \
            the conductance opens with the gap as for the plates, the gap taken from the Newton iterate. \
            Optional; without it (and without [plates]) the surface is sealed, as before. Not with [plates].",
    keys: &[GROUP, PENALTY, SEAL_GAP],
};

#[cfg(test)]
mod tests {
    use super::DrainageSpec;

    #[test]
    fn drainage_is_checked_and_refused_beside_the_plates() {
        let spec: DrainageSpec = toml::from_str("seal_gap = 0.05").unwrap();
        assert_eq!((spec.group.as_str(), spec.penalty), ("surface", 100.0));
        assert_eq!(spec.validate(false), Ok(()));
        let msg = spec.validate(true).unwrap_err();
        assert!(msg.contains("[drainage] is for a scene without [plates]") && msg.contains("plates.seal_gap"), "{msg}");
        for (text, want) in [
            ("seal_gap = 0.0", "drainage.seal_gap = 0: must be positive"),
            ("seal_gap = 1.0\npenalty = -1.0", "drainage.penalty = -1: must be positive"),
        ] {
            let spec: DrainageSpec = toml::from_str(text).unwrap();
            let msg = spec.validate(false).unwrap_err();
            assert!(msg.contains(want), "{text}: {msg}");
        }
        let msg = toml::from_str::<DrainageSpec>("penalty = 3.0").unwrap_err().to_string();
        assert!(msg.contains("seal_gap"), "{msg}");
    }
}
