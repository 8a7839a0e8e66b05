//! `[[tools]]`: rigid tools of revolution (a plane, a sphere, a flat punch, a micropipette),
//! their names, shapes, placement, the surface they touch and their displacement protocol;
//! their keys and checks. The geometry they describe is `physics::tools`, which builds a tool
//! from a checked [`ToolSpec`].

use super::key::{Key, Section, Unset};
use super::mesh::Geometry;
use super::protocol::{self, ProtocolRow};
use crate::range::Range;
use serde::{Deserialize, Serialize};

/// One rigid tool: its profile of revolution and where it is at displacement 0.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ToolSpec {
    /// Names the tool in messages; unique among the tools.
    pub(crate) name: String,
    pub(crate) kind: ToolKind,
    /// The sphere's or the punch's radius (µm).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) radius: Option<f64>,
    /// The radius rounding the punch's edge (µm), ≤ `radius`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) edge_radius: Option<f64>,
    /// The pipette's inner radius R_p (µm).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) inner_radius: Option<f64>,
    /// The pipette's wall thickness (µm).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) wall: Option<f64>,
    /// The radius rounding both corners of the pipette's rim (µm), ≤ `wall` / 2.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) rim_radius: Option<f64>,
    /// The tool's point at displacement 0 (µm): a point of the plane, the sphere's centre, the
    /// centre of the punch's face, the centre of the pipette's mouth.
    pub(crate) origin: [f64; 3],
    /// The axis of revolution, from the tool towards the body (normalised when read).
    pub(crate) axis: [f64; 3],
    /// The body's surface group that can touch the tool.
    #[serde(default = "default_group")]
    pub(crate) group: String,
    /// The tool's protocol along its axis: rows {t, displacement}, {t, force} or
    /// {t, displacement = "held"}, linear between rows of one control, held after the last
    /// (empty: held at 0).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(crate) protocol: Vec<ProtocolRow>,
    /// Whether the tool seals the surface it touches (the default) or lets it drain.
    #[serde(default)]
    pub(crate) drainage: ToolDrainage,
}

fn default_group() -> String {
    "surface".into()
}

/// A tool's effect on the drainage of the surface it touches (`physics::drainage`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub(crate) enum ToolDrainage {
    /// Impermeable: the surface it touches is sealed (glass, steel).
    #[default]
    Sealed,
    /// Permeable, or not in the bath's way: the surface drains as if it were not there.
    Free,
}

/// The shape of a tool's profile.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub(crate) enum ToolKind {
    Plane,
    Sphere,
    Punch,
    Pipette,
}

impl ToolKind {
    /// As the scene writes it.
    pub(crate) fn name(self) -> &'static str {
        match self {
            ToolKind::Plane => "plane",
            ToolKind::Sphere => "sphere",
            ToolKind::Punch => "punch",
            ToolKind::Pipette => "pipette",
        }
    }

    /// The dimension keys this kind needs (every other dimension key is an error).
    fn dimensions(self) -> &'static [Key] {
        match self {
            ToolKind::Plane => &[],
            ToolKind::Sphere => &[RADIUS],
            ToolKind::Punch => &[RADIUS, EDGE_RADIUS],
            ToolKind::Pipette => &[INNER_RADIUS, WALL, RIM_RADIUS],
        }
    }
}

impl ToolSpec {
    /// "[[tools]] \"name\"", the start of every message about this tool.
    fn label(&self) -> String {
        format!("[[tools]] \"{}\"", self.name)
    }

    /// The dimension keys with their values, in the order of `DIMENSIONS`.
    fn dimension_values(&self) -> [Option<f64>; 5] {
        [self.radius, self.edge_radius, self.inner_radius, self.wall, self.rim_radius]
    }

    /// The axis as a unit vector (the checks ensure it has a length).
    pub(crate) fn unit_axis(&self) -> [f64; 3] {
        let n = norm(self.axis);
        self.axis.map(|c| c / n)
    }

    /// The tool alone: a name, its kind's dimensions (each positive; no other's), the rounding
    /// radii within the corners they round, a finite origin and a non-zero axis. What the
    /// geometry needs, so `physics::tools` builds a tool from a spec that passes.
    pub(crate) fn check_shape(&self) -> Result<(), String> {
        if self.name.trim().is_empty() {
            return Err("[[tools]]: every tool needs a name (tools.name = \"bead\", say)".into());
        }
        let label = self.label();
        let needs = self.kind.dimensions();
        for (key, value) in DIMENSIONS.iter().zip(self.dimension_values()) {
            let needed = needs.iter().any(|k| k.name == key.name);
            match (needed, value) {
                (true, Some(v)) => key.check(v).map_err(|m| format!("{label}: {m}"))?,
                (true, None) => {
                    return Err(format!(
                        "{label}: a {} needs {} (µm); it is given by {}",
                        self.kind.name(),
                        key.name,
                        listed(needs)
                    ))
                }
                (false, Some(_)) => {
                    return Err(format!(
                        "{label}: {} is not a dimension of a {}, which has {}: leave it out",
                        key.name,
                        self.kind.name(),
                        if needs.is_empty() { "none".to_string() } else { listed(needs) }
                    ))
                }
                (false, None) => {}
            }
        }
        self.check_roundings(&label)?;
        for (i, x) in self.origin.iter().enumerate() {
            ORIGIN.check_as(&format!("{label}: tools.origin[{i}]"), *x)?;
        }
        for (i, x) in self.axis.iter().enumerate() {
            AXIS.check_as(&format!("{label}: tools.axis[{i}]"), *x)?;
        }
        self.check_protocol(&label)?;
        let n = norm(self.axis);
        if !(n > 0.0 && n.is_finite()) {
            return Err(format!(
                "{label}: tools.axis = {:?} has no direction: give the axis from the tool towards the body, \
                 [0, 0, 1] for a tool below it",
                self.axis
            ));
        }
        Ok(())
    }

    /// The protocol: the rows' checks (`scene::protocol`: displacement, force or `"held"` rows,
    /// a switch two rows at one time).
    fn check_protocol(&self, label: &str) -> Result<(), String> {
        if self.protocol.is_empty() {
            return Ok(());
        }
        protocol::check(&format!("{label}: tools.protocol"), &self.protocol)
    }

    /// The protocol's rows from t = 0: the scene's, after `{ t = 0, displacement = 0 }` unless
    /// a row is at t = 0 (the tool starts at its origin).
    pub(crate) fn rows(&self) -> Vec<ProtocolRow> {
        let mut rows = self.protocol.clone();
        if rows.first().is_none_or(|r| r.t > 0.0) {
            let start = protocol::Displacement::Value(0.0);
            rows.insert(0, ProtocolRow { t: 0.0, displacement: Some(start), force: None });
        }
        rows
    }

    /// A rounding no larger than the corner it rounds: the punch's edge within its radius, the
    /// pipette's rim within half its wall (the rim's two corners are both rounded).
    fn check_roundings(&self, label: &str) -> Result<(), String> {
        match (self.kind, self.dimension_values()) {
            (ToolKind::Punch, [Some(radius), Some(edge), ..]) if edge > radius => Err(format!(
                "{label}: tools.edge_radius = {edge} µm is larger than the punch's radius {radius} µm: the edge \
                 rounding fits within the face; give edge_radius ≤ {radius}"
            )),
            (ToolKind::Pipette, [.., Some(wall), Some(rim)]) if rim > 0.5 * wall => Err(format!(
                "{label}: tools.rim_radius = {rim} µm is larger than half the wall, wall / 2 = {} µm: the rim is \
                 rounded on both corners of the wall; give rim_radius ≤ {} or a thicker wall",
                0.5 * wall,
                0.5 * wall
            )),
            _ => Ok(()),
        }
    }

    /// On a meridian mesh, a tool on the symmetry axis: axis [0, 0, ±1], origin [0, 0, z].
    fn check_meridian(&self) -> Result<(), String> {
        let [ax, ay, _] = self.axis;
        let [ox, oy, _] = self.origin;
        if ax == 0.0 && ay == 0.0 && ox == 0.0 && oy == 0.0 {
            return Ok(());
        }
        Err(format!(
            "{}: tools.axis = {:?} and tools.origin = {:?} put the tool off the symmetry axis, which a meridian \
             mesh (mesh.geometry = \"axisymmetric\") cannot hold: give axis = [0, 0, ±1] and origin = [0, 0, z], or \
             use the 3-D mesh (mesh.geometry = \"solid\") for a tool off the axis",
            self.label(),
            self.axis,
            self.origin
        ))
    }
}

/// Every tool's shape; names unique; on a meridian mesh, every tool on the axis. An axis that is
/// not of unit length is read as its direction, with a note.
pub(crate) fn validate(tools: &[ToolSpec], geometry: Geometry, notes: &mut Vec<String>) -> Result<(), String> {
    for (i, t) in tools.iter().enumerate() {
        t.check_shape()?;
        if let Some(first) = tools[..i].iter().find(|o| o.name == t.name) {
            return Err(format!(
                "[[tools]]: two tools are named \"{}\" (a {} and a {}): give each its own tools.name",
                t.name,
                first.kind.name(),
                t.kind.name()
            ));
        }
        if geometry == Geometry::Axisymmetric {
            t.check_meridian()?;
        }
        if (norm(t.axis) - 1.0).abs() > 1e-6 {
            notes.push(format!(
                "{}: tools.axis = {:?} is not a unit vector: read as its direction {:?}",
                t.label(),
                t.axis,
                t.unit_axis()
            ));
        }
    }
    Ok(())
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// "tools.a, tools.b and tools.c".
fn listed(keys: &[Key]) -> String {
    let names: Vec<&str> = keys.iter().map(|k| k.name).collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => names.join(""),
    }
}

const NAME: Key = Key::new("tools.name", "", Unset::Required, "the tool's name, in messages").rule("unique, not empty");
const KIND: Key = Key::new(
    "tools.kind",
    "",
    Unset::Required,
    "the profile of revolution: `plane`, `sphere`, `punch` (a flat punch, its edge rounded) or `pipette`",
)
.rule("each kind takes its own dimensions, and only those");
const RADIUS: Key = Key::new(
    "tools.radius",
    "µm",
    Unset::Absent("required for a sphere or a punch"),
    "the sphere's or the flat punch's radius",
)
.range(Range::POSITIVE);
const EDGE_RADIUS: Key =
    Key::new("tools.edge_radius", "µm", Unset::Absent("required for a punch"), "the radius rounding the punch's edge")
        .range(Range::POSITIVE)
        .rule("≤ radius");
const INNER_RADIUS: Key = Key::new(
    "tools.inner_radius",
    "µm",
    Unset::Absent("required for a pipette"),
    "the pipette's inner radius R_p (its bore)",
)
.range(Range::POSITIVE);
const WALL: Key =
    Key::new("tools.wall", "µm", Unset::Absent("required for a pipette"), "the thickness of the pipette's wall")
        .range(Range::POSITIVE);
const RIM_RADIUS: Key = Key::new(
    "tools.rim_radius",
    "µm",
    Unset::Absent("required for a pipette"),
    "the radius rounding both corners of the pipette's rim",
)
.range(Range::POSITIVE)
.rule("≤ wall / 2");
const ORIGIN: Key = Key::new(
    "tools.origin",
    "µm",
    Unset::Required,
    "the tool's point at displacement 0: a point of the plane, the sphere's centre, the centre of the punch's \
     face or of the pipette's mouth",
)
.range(Range::FINITE)
.rule("[0, 0, z] on a meridian mesh");
const AXIS: Key = Key::new(
    "tools.axis",
    "",
    Unset::Required,
    "the axis of revolution, from the tool towards the body (read as its direction)",
)
.range(Range::FINITE)
.rule("not zero; [0, 0, ±1] on a meridian mesh");

const GROUP: Key =
    Key::new("tools.group", "", Unset::Value("\"surface\""), "the body's surface group that can touch the tool");
const PROTOCOL: Key = Key::new(
    "tools.protocol",
    "s, µm, µN",
    Unset::Absent("held at 0"),
    "the tool's protocol along its axis (towards the body positive): rows `{ t = 0.0, displacement = 0.0 }` \
     (µm), `{ t = 5.0, force = 0.5 }` (µN, compressive, full body: its position is then an unknown) or \
     `{ t = 60.0, displacement = \"held\" }` (where force control left it), linear between rows of one \
     control, held after the last; a switch is two rows at one time",
)
.rule("increasing t ≥ 0; force > 0; a force-controlled tool must touch the body when its control starts");

const DRAINAGE: Key = Key::new(
    "tools.drainage",
    "",
    Unset::Value("\"sealed\""),
    "`sealed`: the tool is impermeable, the surface it touches does not drain; `free`: it drains as if the \
     tool were not there",
)
.rule("drains only with [plates] or [drainage]")
.enters("numerics.md: Drainage off the tools");

/// The dimension keys, in the order of [`ToolSpec::dimension_values`].
const DIMENSIONS: [Key; 5] = [RADIUS, EDGE_RADIUS, INNER_RADIUS, WALL, RIM_RADIUS];

pub(super) const SECTION: Section = Section {
    title: "[[tools]]",
    enters: "",
    about: "Rigid tools of revolution about their own axis: a plane, a sphere, a flat punch with a rounded edge, \
            a micropipette (a tube with a rounded rim). Each is placed by its origin and its axis, which points \
            from the tool towards the body.",
    keys: &[NAME, KIND, RADIUS, EDGE_RADIUS, INNER_RADIUS, WALL, RIM_RADIUS, ORIGIN, AXIS, GROUP, PROTOCOL, DRAINAGE],
};

#[cfg(test)]
mod tests {
    use super::{validate, ToolSpec, SECTION};
    use crate::scene::mesh::Geometry;
    use crate::scene::protocol::Control;

    /// The issue's three tools: a dish, a bead, a pipette (the geometry keys of each).
    const TOOLS: &str = r#"
[[tools]]
name = "dish"
kind = "plane"
origin = [0.0, 0.0, 0.0]
axis = [0.0, 0.0, 1.0]

[[tools]]
name = "bead"
kind = "sphere"
radius = 50.0
origin = [0.0, 0.0, 251.0]
axis = [0.0, 0.0, -1.0]

[[tools]]
name = "pipette"
kind = "pipette"
inner_radius = 35.0
wall = 20.0
rim_radius = 5.0
origin = [0.0, 0.0, 350.0]
axis = [0.0, 0.0, -1.0]
"#;

    #[derive(serde::Deserialize)]
    struct File {
        tools: Vec<ToolSpec>,
    }

    fn parse(text: &str) -> Result<Vec<ToolSpec>, String> {
        toml::from_str::<File>(text).map(|f| f.tools).map_err(|e| e.to_string())
    }

    /// The tools with line `from` of TOOLS replaced by `to`, validated on `geometry`.
    fn edited(from: &str, to: &str, geometry: Geometry) -> Result<Vec<String>, String> {
        assert!(TOOLS.contains(from), "no `{from}`");
        let tools = parse(&TOOLS.replacen(from, to, 1))?;
        let mut notes = Vec::new();
        validate(&tools, geometry, &mut notes).map(|_| notes)
    }

    #[track_caller]
    fn refused(from: &str, to: &str, parts: &[&str]) {
        let msg = edited(from, to, Geometry::Solid).expect_err(to);
        for part in parts {
            assert!(msg.contains(part), "`{to}`: `{part}` expected in: {msg}");
        }
    }

    #[test]
    fn the_issues_tools_are_accepted_on_both_meshes() {
        for g in [Geometry::Solid, Geometry::Axisymmetric] {
            assert_eq!(edited("", "", g), Ok(vec![]));
        }
        let punch = "kind = \"punch\"\nradius = 40.0\nedge_radius = 40.0";
        assert_eq!(edited("kind = \"sphere\"\nradius = 50.0", punch, Geometry::Solid), Ok(vec![]));
        assert_eq!(edited("rim_radius = 5.0", "rim_radius = 10.0", Geometry::Solid), Ok(vec![]));
        // An axis off the aggregate's, in 3-D; a non-unit axis is read as its direction.
        let notes = edited("axis = [0.0, 0.0, -1.0]", "axis = [0.0, 0.6, -1.6]", Geometry::Solid).unwrap();
        assert!(
            notes.len() == 1 && notes[0].contains("\"bead\"") && notes[0].contains("not a unit vector"),
            "{notes:?}"
        );
    }

    #[test]
    fn every_malformed_tool_is_refused_naming_the_key_and_the_fix() {
        let bead = "radius = 50.0";
        for (to, want) in
            [("radius = 0.0", "tools.radius = 0: must be positive"), ("radius = -5.0", "= -5"), ("radius = nan", "NaN")]
        {
            refused(bead, to, &["[[tools]] \"bead\"", want]);
        }
        refused(bead, "", &["a sphere needs tools.radius"]);
        refused(
            bead,
            "radius = 50.0\nwall = 3.0",
            &["tools.wall is not a dimension of a sphere, which has tools.radius"],
        );
        refused(
            "kind = \"plane\"",
            "kind = \"plane\"\nradius = 3.0",
            &["\"dish\"", "not a dimension of a plane, which has none"],
        );
        let sphere = "kind = \"sphere\"\nradius = 50.0";
        refused(sphere, "kind = \"punch\"\nradius = 40.0", &["a punch needs tools.edge_radius"]);
        refused(
            sphere,
            "kind = \"punch\"\nradius = 40.0\nedge_radius = 0.0",
            &["tools.edge_radius = 0: must be positive"],
        );
        refused(
            sphere,
            "kind = \"punch\"\nradius = 40.0\nedge_radius = 41.0",
            &["tools.edge_radius = 41 µm is larger than the punch's radius 40 µm", "edge_radius ≤ 40"],
        );
        refused(
            "inner_radius = 35.0",
            "inner_radius = 0.0",
            &["\"pipette\"", "tools.inner_radius = 0: must be positive"],
        );
        refused("wall = 20.0", "wall = -20.0", &["tools.wall = -20: must be positive"]);
        refused("rim_radius = 5.0", "rim_radius = 0.0", &["tools.rim_radius = 0: must be positive"]);
        refused(
            "rim_radius = 5.0",
            "rim_radius = 10.5",
            &[
                "tools.rim_radius = 10.5 µm is larger than half the wall, wall / 2 = 10 µm",
                "rim_radius ≤ 10 or a thicker wall",
            ],
        );
        refused(
            "wall = 20.0\nrim_radius = 5.0",
            "rim_radius = 5.0",
            &["a pipette needs tools.wall (µm); it is given by tools.inner_radius, tools.wall and tools.rim_radius"],
        );
        refused(
            "axis = [0.0, 0.0, 1.0]",
            "axis = [0.0, 0.0, 0.0]",
            &["\"dish\"", "tools.axis = [0.0, 0.0, 0.0] has no direction"],
        );
        refused("axis = [0.0, 0.0, 1.0]", "axis = [0.0, inf, 1.0]", &["tools.axis[1] = inf: must be finite"]);
        refused("origin = [0.0, 0.0, 251.0]", "origin = [0.0, nan, 251.0]", &["tools.origin[1] = NaN: must be finite"]);
        refused("name = \"dish\"", "name = \" \"", &["every tool needs a name"]);
        refused("name = \"bead\"", "name = \"dish\"", &["two tools are named \"dish\" (a plane and a sphere)"]);
    }

    #[test]
    fn a_meridian_mesh_holds_only_tools_on_its_axis() {
        for (from, to) in [
            ("axis = [0.0, 0.0, -1.0]", "axis = [0.0, 0.1, -1.0]"),
            ("origin = [0.0, 0.0, 251.0]", "origin = [15.0, 0.0, 251.0]"),
        ] {
            assert!(edited(from, to, Geometry::Solid).is_ok(), "{to} in 3-D");
            let msg = edited(from, to, Geometry::Axisymmetric).unwrap_err();
            assert!(msg.contains("\"bead\"") && msg.contains("off the symmetry axis"), "{msg}");
            assert!(msg.contains("mesh.geometry = \"solid\""), "the fix: {msg}");
        }
    }

    #[test]
    fn unknown_keys_and_kinds_are_refused_by_name() {
        use super::ToolDrainage::{Free, Sealed};
        let msg = edited("kind = \"plane\"", "kind = \"cone\"", Geometry::Solid).unwrap_err();
        assert!(msg.contains("cone") && msg.contains("pipette"), "{msg}");
        // Friction is not a property of these tools: refused by name.
        let msg = edited("radius = 50.0", "radius = 50.0\nfriction = 0.1", Geometry::Solid).unwrap_err();
        assert!(msg.contains("unknown field `friction`"), "{msg}");
        // A tool seals unless it is free; nothing else.
        let tools = parse(&TOOLS.replacen("radius = 50.0", "radius = 50.0\ndrainage = \"free\"", 1)).unwrap();
        assert_eq!(tools.iter().map(|t| t.drainage).collect::<Vec<_>>(), [Sealed, Free, Sealed]);
        let msg = edited("radius = 50.0", "radius = 50.0\ndrainage = \"porous\"", Geometry::Solid).unwrap_err();
        assert!(msg.contains("porous") && msg.contains("sealed") && msg.contains("free"), "{msg}");
    }

    #[test]
    fn the_section_declares_every_key_of_a_tool() {
        let mut all = parse(TOOLS).unwrap().remove(2);
        (all.radius, all.edge_radius) = (Some(1.0), Some(1.0));
        all.protocol = vec![super::ProtocolRow {
            t: 0.0,
            displacement: Some(super::protocol::Displacement::Value(0.0)),
            force: None,
        }];
        let text = toml::to_string(&all).unwrap();
        // Top-level `key = value` lines, and the protocol's rows as the array of tables they are.
        let top = text.split("\n[[").next().unwrap();
        let rows = text.lines().filter_map(|l| l.strip_prefix("[[")?.strip_suffix("]]"));
        let written: Vec<String> = top
            .lines()
            .filter_map(|l| l.split_once(" = ").map(|(k, _)| k))
            .chain(rows)
            .map(|k| format!("tools.{k}"))
            .collect();
        let mut declared: Vec<String> = SECTION.keys.iter().map(|k| k.name.to_string()).collect();
        let mut written = written;
        written.sort();
        declared.sort();
        assert_eq!(written, declared);
    }

    #[test]
    fn a_scenes_tools_are_read_with_their_protocols_and_refused_when_out_of_order() {
        let text = crate::scene::BUILTIN.iter().find(|(n, _)| *n == "reference").unwrap().1;
        let dir = std::env::temp_dir().join(format!("poroplast-tools-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("tools.toml");
        let bead = TOOLS.replace(
            "axis = [0.0, 0.0, -1.0]\n\n[[tools]]\nname = \"pipette\"",
            "axis = [0.0, 0.0, -1.0]\nprotocol = [ { t = 1.0, displacement = 2.0 } ]\n\n[[tools]]\nname = \"pipette\"",
        );
        assert_ne!(bead, TOOLS);
        std::fs::write(&path, format!("{text}\n{bead}")).unwrap();
        let loaded = crate::scene::LoadedScene::load(&path.display().to_string(), &[]).unwrap();
        let tools = &loaded.scene.tools;
        assert_eq!(tools.iter().map(|t| t.name.as_str()).collect::<Vec<_>>(), ["dish", "bead", "pipette"]);
        let at = |t: &ToolSpec| t.rows().iter().map(|r| (r.t, r.control("", 0).unwrap())).collect::<Vec<_>>();
        let d = |v: f64| Control::Displacement(Some(v));
        assert_eq!(at(&tools[1]), vec![(0.0, d(0.0)), (1.0, d(2.0))], "from (0, 0), then the rows");
        assert_eq!(at(&tools[0]), vec![(0.0, d(0.0))], "no protocol: held at 0");
        assert_eq!(tools[0].group, "surface");
        let late = bead.replace(
            "{ t = 1.0, displacement = 2.0 }",
            "{ t = 1.0, displacement = 2.0 }, { t = 1.0, displacement = 3.0 }",
        );
        std::fs::write(&path, format!("{text}\n{late}")).unwrap();
        let msg = crate::scene::LoadedScene::load(&path.display().to_string(), &[]).err().unwrap().to_string();
        assert!(
            msg.contains("\"bead\"") && msg.contains("rows 1 and 2: two rows at 1 s with the same control"),
            "{msg}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
