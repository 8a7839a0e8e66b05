"""The docs agree with the code on scene keys:

* every parameter a shipped `.geo` declares (`DefineConstant[ NAME = ... ]`) is documented in
  docs/scene-reference.md as `mesh.params.NAME`, and every size a shipped scene gives (in
  `mesh.params` or `mesh.relative_sizes`) is a parameter of its `.geo` (a typo is meshed with
  the .geo's default, silently);
* the default of every enumerated scene key (a serde enum with a `#[default]` variant in src/,
  such as `material.remodelling.form`, `integrator`, `plates.drainage_gap`) is the one the
  reference gives, and a doc line that says `KEY = "VALUE"` and "default" names the real default;
* no shipped scene or study file (meshes/scenes, meshes/sweeps) uses a deprecated key (those
  whose declaration in src/scene/ reads "deprecated: ..."), and howto-sweep.md prints the
  shipped study as it is.

Pure Python over the sources, no solver; well under a second.
"""

import re
import tomllib
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
REFERENCE = ROOT / "docs" / "scene-reference.md"


def geo_params(path):
    """The parameters a .geo file takes: its `DefineConstant[ NAME = default ]` declarations
    (what `gmsh -setnumber NAME` sets)."""
    return re.findall(r"DefineConstant\s*\[\s*(\w+)\s*=", Path(path).read_text())


def reference_rows():
    """docs/scene-reference.md's key tables: {key: (unit, default, valid, description)}."""
    rows = {}
    for line in REFERENCE.read_text(encoding="utf-8").splitlines():
        m = re.match(r"\| `([^`]+)` \|(.*)\|\s*$", line)
        if m:
            cells = [c.strip() for c in m.group(2).split(" | ")]
            rows.setdefault(m.group(1), cells)
    return rows


def rust_sources():
    return {p: p.read_text(encoding="utf-8") for p in sorted((ROOT / "src").rglob("*.rs"))}


def snake(name):
    return re.sub(r"(?<!^)(?=[A-Z])", "_", name).lower()


def enum_defaults(sources):
    """{enum name: the TOML spelling of its `#[default]` variant} for every serde enum of src/
    with one: the variant's `#[serde(rename = "...")]`, else its name under the enum's
    `rename_all` (snake_case or lowercase)."""
    out = {}
    for text in sources.values():
        for m in re.finditer(r"((?:#\[[^\]]*\]\s*)*)pub(?:\(crate\))? enum (\w+)\s*\{(.*?)\n\}", text, re.S):
            attrs, name, body = m.groups()
            d = re.search(r"#\[default\]\s*((?:#\[[^\]]*\]\s*|///[^\n]*\n\s*)*)(\w+)", body)
            if d is None:
                continue
            rename = re.search(r'#\[serde\(rename = "([^"]+)"\)\]', d.group(1))
            rule = re.search(r'rename_all = "(\w+)"', attrs)
            variant = d.group(2)
            if rename:
                out[name] = rename.group(1)
            elif rule and rule.group(1) == "snake_case":
                out[name] = snake(variant)
            elif rule and rule.group(1) == "lowercase":
                out[name] = variant.lower()
            else:
                out[name] = variant
    return out


def enum_fields(sources, enums):
    """{scene field name: enum} for the fields of src/scene/'s structs whose type is such an enum
    (`pub drainage_gap: DrainageGap,`)."""
    out = {}
    for path, text in sources.items():
        if "scene" not in path.parts:
            continue
        for field, ty in re.findall(r"pub(?:\(crate\))? (\w+): (\w+),", text):
            if ty in enums:
                out[field] = ty
    return out


def deprecated_keys(sources):
    """The keys src/scene/ declares as deprecated (their description starts with "deprecated")."""
    keys = []
    for path, text in sources.items():
        if "scene" in path.parts:
            keys += re.findall(r'Key::new\(\s*"([\w.]+)",\s*"[^"]*",\s*Unset::\w+\([^)]*\),\s*"deprecated', text)
    return keys


def flat_keys(table, prefix=""):
    """The dotted keys of a TOML table (lists of tables by their entries' keys)."""
    out = []
    for k, v in table.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict):
            out += [key] + flat_keys(v, key + ".")
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            out += [key] + [x for e in v for x in flat_keys(e, key + ".")]
        else:
            out.append(key)
    return out


def study_keys(study):
    """The scene keys a study file overrides: its `set` entries, its grid axes' keys and its
    cases' `set` entries."""
    sets = list(study.get("set", []))
    sets += [s for c in study.get("case", []) for s in c.get("set", [])]
    keys = [s.partition("=")[0].strip() for s in sets]
    for axis in study.get("grid", []):
        keys += [axis["key"]] if "key" in axis else list(axis.get("keys", []))
    return keys


def doc_files():
    files = [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md")) + sorted((ROOT / "docs" / "decisions").glob("*.md"))
    # The journals in docs/history record what was true then; the reference is generated.
    return [f for f in files if f.exists() and f != REFERENCE]


class GeoParameters(unittest.TestCase):
    def test_every_geo_parameter_is_in_the_key_reference(self):
        rows = reference_rows()
        geos = sorted((ROOT / "meshes").glob("*.geo"))
        self.assertGreaterEqual(len(geos), 6)
        missing = [f"{g.name}: mesh.params.{p}" for g in geos for p in geo_params(g)
                   if f"mesh.params.{p}" not in rows]
        self.assertEqual(missing, [], "document these in src/scene/mesh.rs's keys, then regenerate "
                                      "docs/scene-reference.md (`poroplast scenes --keys`)")

    def test_the_parameters_are_read_from_every_geo(self):
        # The reader finds what the spheres declare (a check that the check can fail).
        self.assertEqual(geo_params(ROOT / "meshes" / "sphere_meridian.geo"),
                         ["R", "h", "h_pole", "r_pole", "h_edge", "r_edge", "w_edge", "h_surf", "w_surf"])
        self.assertEqual(geo_params(ROOT / "meshes" / "column.geo"), ["H", "W", "h", "h_top"])

    def test_shipped_scenes_give_only_parameters_their_geo_takes(self):
        scenes = sorted((ROOT / "meshes" / "scenes").glob("*.toml"))
        self.assertGreater(len(scenes), 10)
        wrong = []
        for s in scenes:
            mesh = tomllib.loads(s.read_text())["mesh"]
            geos = [mesh[k] for k in ("geo", "meridian") if k in mesh]
            takes = {p for g in geos for p in geo_params(ROOT / "meshes" / g)}
            given = set(mesh.get("params", {})) | set(mesh.get("relative_sizes", {}))
            wrong += [f"{s.name}: {k} (not a parameter of {', '.join(geos)})" for k in sorted(given - takes)]
        self.assertEqual(wrong, [])


class EnumDefaults(unittest.TestCase):
    def setUp(self):
        self.sources = rust_sources()
        self.defaults = enum_defaults(self.sources)
        self.fields = enum_fields(self.sources, self.defaults)

    def test_the_rust_defaults_are_read(self):
        # The three the docs disagreed on (see the module docs), read from the enums.
        self.assertEqual(self.defaults["FlowForm"], "40b")
        self.assertEqual(self.defaults["Integrator"], "implicit")
        self.assertEqual(self.defaults["DrainageGap"], "predicted")
        self.assertEqual({k: self.fields[k] for k in ("form", "integrator", "drainage_gap")},
                         {"form": "FlowForm", "integrator": "Integrator", "drainage_gap": "DrainageGap"})

    def test_the_reference_gives_each_enums_default(self):
        rows = reference_rows()
        checked = 0
        for key, (unit, default, *_rest) in rows.items():
            field = key.rsplit(".", 1)[-1]
            if field in self.fields and default.startswith('`"'):
                want = self.defaults[self.fields[field]]
                self.assertEqual(default, f'`"{want}"`', f"{key}: the reference's default against src/")
                checked += 1
        self.assertGreaterEqual(checked, 3)

    def test_the_docs_name_the_real_defaults(self):
        checked, wrong = 0, []
        for doc in doc_files():
            for n, line in enumerate(doc.read_text(encoding="utf-8").splitlines(), 1):
                if "default" not in line:
                    continue
                for field, enum in self.fields.items():
                    said = re.findall(rf'\b{field} = "([^"]+)"', line)
                    if not said:
                        continue
                    checked += 1
                    real = self.defaults[enum]
                    # `KEY = "V" ... (default)` with no quoted value between: V is claimed the default
                    # (`(default "X")` names X instead).
                    claimed = re.findall(rf'\b{field} = "([^"]+)"[^"]*?\(default\b(?!\s*`?")', line)
                    if any(v != real for v in claimed) or f'"{real}"' not in line:
                        wrong.append(f"{doc.relative_to(ROOT)}:{n}: {field}'s default is \"{real}\": {line.strip()}")
        self.assertEqual(wrong, [])
        self.assertGreaterEqual(checked, 3)


class DeprecatedKeys(unittest.TestCase):
    def test_no_shipped_scene_or_study_uses_a_deprecated_key(self):
        deprecated = deprecated_keys(rust_sources())
        self.assertIn("plates.t_ramp", deprecated)
        self.assertIn("plates.t_end", deprecated)
        # The reference (generated from the same declarations) says so too.
        rows = reference_rows()
        self.assertTrue(all(rows[k][3].startswith("deprecated") for k in deprecated), deprecated)
        used = []
        for s in sorted((ROOT / "meshes" / "scenes").glob("*.toml")):
            used += [f"{s.name}: {k}" for k in flat_keys(tomllib.loads(s.read_text())) if k in deprecated]
        studies = sorted((ROOT / "meshes" / "sweeps").glob("*.toml"))
        self.assertGreaterEqual(len(studies), 1)
        for s in studies:
            used += [f"{s.name}: {k}" for k in study_keys(tomllib.loads(s.read_text())) if k in deprecated]
        self.assertEqual(used, [], "write plates.ramp, plates.hold and plates.release instead")

    def test_the_sweep_howto_shows_the_shipped_study(self):
        # howto-sweep.md says "start from the shipped example" and prints it: the same values.
        md = (ROOT / "docs" / "howto-sweep.md").read_text(encoding="utf-8")
        block = re.findall(r"^```toml\n(.*?)^```", md, re.S | re.M)[0]
        shipped = tomllib.loads((ROOT / "meshes" / "sweeps" / "mu_compression_axi.toml").read_text())
        self.assertEqual(tomllib.loads(block), shipped)

    def test_study_keys_are_read(self):
        study = tomllib.loads('set = ["time.t_end=10"]\n[[grid]]\nkeys = ["plates.compression", "plates.t_ramp"]\n'
                              'values = [[0.2, 3.3]]\n[[case]]\nset = ["plates.t_end=40"]\n')
        self.assertEqual(study_keys(study), ["time.t_end", "plates.t_end", "plates.compression", "plates.t_ramp"])


if __name__ == "__main__":
    unittest.main()
