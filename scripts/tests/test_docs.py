"""The docs' cross-references resolve, they cite no internal issue numbers, and the command-line
reference lists every subcommand and flag of src/cli.rs.

Checked in README.md, CHANGELOG.md, scripts/README.md and docs/**/*.md (the generated
docs/scene-reference.md included):

* Markdown links and images to local files exist; a `#anchor` names a heading of the target
  (GitHub's slugs);
* `model.md §n` (and `§n–§m`) references, also in src/ and scripts/, name a numbered section;
* prose references to a section, `numerics.md, *Title*` or `performance.md, "Title"`, name a
  heading (or a bold run-in heading) of that file, also in src/, meshes/ and scripts/;
* no "issue N": a reader cannot resolve it;
* the commands of the docs' code blocks (and the shipped sweep's comments) start runs on several
  ranks as `poroplast mpirun -n N run|resume|sweep`, not under a bare `mpirun`.

Pure Python, no solver; well under a second.
"""

import re
import unittest
import unicodedata
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"


def doc_files():
    files = [ROOT / "README.md", ROOT / "CHANGELOG.md", ROOT / "scripts" / "README.md"]
    files += sorted(DOCS.rglob("*.md"))
    return [f for f in files if f.exists()]


def strip_code(text):
    """The text without fenced code blocks and inline code (links there are not links)."""
    text = re.sub(r"^```.*?^```", "", text, flags=re.S | re.M)
    return re.sub(r"`[^`\n]*`", "", text)


def slug(heading):
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    s = heading.strip().lower()
    s = re.sub(r"`", "", s)
    s = "".join(c for c in s if c in " -_" or unicodedata.category(c)[0] in "LN")
    return s.replace(" ", "-")


def headings(path):
    out, in_code = [], False
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            in_code = not in_code
        elif not in_code and re.match(r"#{1,6} ", line):
            out.append(line.lstrip("#").strip())
    return out


def anchors(path):
    seen, out = {}, set()
    for h in headings(path):
        a = slug(h)
        n = seen.get(a, 0)
        out.add(a if n == 0 else f"{a}-{n}")
        seen[a] = n + 1
    return out


def norm(s):
    s = s.lower().replace("–", "-").replace("—", "-").replace("`", "")
    return re.sub(r"\s+", " ", s).strip()


def titles(path):
    """Headings and bold run-in headings (`**Title.**`, `* **Title**`) of a page, normalised."""
    text = path.read_text(encoding="utf-8")
    bold = re.findall(r"\*\*([^*\n]+)\*\*", text)
    return [norm(t) for t in headings(path) + bold]


def resolve(name, source):
    """A doc named in prose: `docs/x.md` from the root, `x.md` beside the source or in docs/."""
    for base in (ROOT, source.parent, DOCS):
        p = (base / name).resolve()
        if p.exists():
            return p
    return None


class DocsTest(unittest.TestCase):
    def test_no_issue_numbers(self):
        bad = []
        for f in doc_files():
            for i, line in enumerate(f.read_text(encoding="utf-8").splitlines(), 1):
                if re.search(r"\bissues? #?\d+", line, re.I):
                    bad.append(f"{f.relative_to(ROOT)}:{i}: {line.strip()[:90]}")
        self.assertEqual(bad, [], "internal issue numbers in the docs:\n" + "\n".join(bad))

    def test_links_resolve(self):
        bad = []
        for f in doc_files():
            for target in re.findall(r"\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)", strip_code(f.read_text(encoding="utf-8"))):
                if re.match(r"[a-z]+:", target):
                    continue  # http(s), mailto
                path, _, anchor = target.partition("#")
                dest = (f.parent / path).resolve() if path else f
                if not dest.exists():
                    bad.append(f"{f.relative_to(ROOT)}: ({target}): no such file")
                elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
                    bad.append(f"{f.relative_to(ROOT)}: ({target}): no heading with that anchor")
        self.assertEqual(bad, [], "broken links:\n" + "\n".join(bad))

    def test_section_numbers_resolve(self):
        files = doc_files() + sorted((ROOT / "src").rglob("*.rs")) + sorted((ROOT / "scripts").rglob("*.py"))
        bad = []
        pattern = re.compile(r"([\w/-]+\.md) ?§ ?(\d+)((?:\s*[–,-]\s*§ ?\d+)*)")
        for f in files:
            text = f.read_text(encoding="utf-8")
            for m in pattern.finditer(text):
                dest = resolve(m.group(1), f) or resolve("docs/" + Path(m.group(1)).name, f)
                nums = [m.group(2)] + re.findall(r"§ ?(\d+)", m.group(3))
                if re.match(r"\s*[–-]", m.group(3)):  # a range §a–§b
                    nums = [str(n) for n in range(int(nums[0]), int(nums[-1]) + 1)]
                if dest is None:
                    bad.append(f"{f.relative_to(ROOT)}: {m.group(0)}: no such file")
                    continue
                have = {re.match(r"§\s*(\d+)", h).group(1) for h in headings(dest) if re.match(r"§\s*\d+", h)}
                bad += [f"{f.relative_to(ROOT)}: {m.group(0)}: no §{n}" for n in nums if n not in have]
        self.assertEqual(bad, [], "section references that do not resolve:\n" + "\n".join(bad))

    def test_named_sections_resolve(self):
        bad = []
        pattern = re.compile(r"([\w/-]+\.md)[,:]? \(?(?:\"([^\"]{1,80})\"|\*([^*]{1,80})\*)")
        others = sorted((ROOT / "src").rglob("*.rs")) + sorted((ROOT / "meshes").rglob("*.toml")) + sorted((ROOT / "scripts").rglob("*.toml"))
        others += [p for p in sorted((ROOT / "scripts").rglob("*.py")) if p.name != "test_docs.py"]
        for f in doc_files() + others:
            for m in pattern.finditer(f.read_text(encoding="utf-8")):
                name = re.sub(r"\n\s*(?://[/!]?|#)?\s*", " ", m.group(2) or m.group(3))  # across comment lines
                dest = resolve(m.group(1), f)
                if dest is None:
                    bad.append(f"{f.relative_to(ROOT)}: {m.group(0)}: no such file")
                elif not any(norm(name).rstrip(".") in t for t in titles(dest)):
                    bad.append(f"{f.relative_to(ROOT)}: {m.group(0)}: no such section")
        self.assertEqual(bad, [], "named sections that do not resolve:\n" + "\n".join(bad))

    def test_runs_on_several_ranks_start_through_the_launcher(self):
        # A command a reader pastes runs on several ranks as `poroplast mpirun -n N run ...`: a
        # Ctrl-C then stops it with a checkpoint and exit code 75; a bare `mpirun` exits with 1.
        bare = re.compile(r"^\s*mpirun\b.*\bporoplast (run|resume|sweep)\b")
        bad, launched = [], 0
        files = [f for f in doc_files() if "history" not in f.parts and f.name != "CHANGELOG.md"]
        for f in files + sorted((ROOT / "meshes" / "sweeps").glob("*.toml")):
            text = f.read_text(encoding="utf-8")
            blocks = re.findall(r"^```(?:sh|bash)?\n(.*?)^```", text, re.S | re.M) if f.suffix == ".md" else \
                [re.sub(r"^#\s?", "", line) for line in text.splitlines() if line.startswith("#")]
            for line in "\n".join(blocks).splitlines():
                launched += "poroplast mpirun -n" in line
                if bare.search(line):
                    bad.append(f"{f.relative_to(ROOT)}: {line.strip()}")
        self.assertEqual(bad, [], "start these with `target/release/poroplast mpirun -n N COMMAND`")
        self.assertGreaterEqual(launched, 10)

    def test_cli_reference_lists_every_subcommand_and_flag(self):
        src = (ROOT / "src" / "cli.rs").read_text(encoding="utf-8")
        ref = (DOCS / "reference-cli.md").read_text(encoding="utf-8")
        body = src[src.index("pub enum Command") :]
        bad = []
        # Each variant `Name {` (or `Name,`) of the enum, with the #[arg(...)] fields up to the next variant.
        for m in re.finditer(r"^    (\w+) \{(.*?)^    \}", body, re.S | re.M):
            sub = m.group(1).lower()
            section = re.search(rf"^## poroplast {sub}\n(.*?)(?=^## |\Z)", ref, re.S | re.M)
            if section is None:
                bad.append(f"no section '## poroplast {sub}'")
                continue
            for arg, field in re.findall(r"#\[arg\(([^\]]*)\)\]\s*(?:pub )?(\w+):", m.group(2)):
                if "last = true" in arg:
                    flag = "-- "
                elif "long" in arg:
                    named = re.search(r'long = "([^"]+)"', arg)
                    flag = "--" + (named.group(1) if named else field.replace("_", "-"))
                else:
                    continue
                if flag not in section.group(1):
                    bad.append(f"poroplast {sub}: {flag.strip()} is not in its section")
        self.assertEqual(bad, [], "docs/reference-cli.md is behind src/cli.rs:\n" + "\n".join(bad))


if __name__ == "__main__":
    unittest.main()
