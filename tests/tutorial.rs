//! docs/tutorial.md, run as a reader runs it (in the slow tier: its fit takes a minute): every ```sh block in order, by bash, in a fresh
//! directory that has the repository's `scripts/`, `meshes/` and `ci/` and the built binary at
//! `target/release/poroplast`. A block preceded by `<!-- tutorial test: skip ... -->` is not run
//! (the machine's set-up and build, which the test suite has done). A ```text block right after a
//! command block is what the reader is told to expect: each of its lines must appear in what the
//! commands printed (stdout and stderr), so the numbers the tutorial quotes are the run's.

mod common;
use common::*;
use std::path::Path;
use std::process::Command;

const MANIFEST: &str = env!("CARGO_MANIFEST_DIR");

/// A block of the tutorial: its info string (`sh`, `text`, ...), its text, and whether the
/// line before it asks the test to skip it.
struct Block {
    lang: String,
    text: String,
    skip: bool,
}

fn blocks(md: &str) -> Vec<Block> {
    let (mut out, mut lines) = (Vec::new(), md.lines());
    let mut previous = "";
    while let Some(line) = lines.next() {
        if let Some(lang) = line.strip_prefix("```") {
            let mut text = String::new();
            for l in lines.by_ref() {
                if l.starts_with("```") {
                    break;
                }
                text.push_str(l);
                text.push('\n');
            }
            let skip = previous.starts_with("<!-- tutorial test: skip");
            out.push(Block { lang: lang.trim().to_string(), text, skip });
            previous = "";
        } else if !line.trim().is_empty() {
            previous = line.trim();
        }
    }
    out
}

/// The tutorial's directory: the repository's parts it uses, linked, and the built binary.
fn workspace() -> std::path::PathBuf {
    let dir = scratch("tutorial");
    for part in ["scripts", "meshes", "ci"] {
        std::os::unix::fs::symlink(Path::new(MANIFEST).join(part), dir.join(part)).unwrap();
    }
    std::fs::create_dir_all(dir.join("target/release")).unwrap();
    std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_poroplast"), dir.join("target/release/poroplast")).unwrap();
    dir
}

#[test]
#[ignore = "slow tier: the tutorial's fit is 21 runs (about a minute on one core)"]
fn the_tutorial_runs_as_written() {
    let _cores = cores(2); // its commands run on up to 2 ranks, one at a time
    let md = std::fs::read_to_string(Path::new(MANIFEST).join("docs/tutorial.md")).unwrap();
    let all = blocks(&md);
    assert!(all.iter().filter(|b| b.lang == "sh" && !b.skip).count() >= 5, "too few commands to be a tutorial");
    let dir = workspace();
    let mut printed = String::new();
    for (i, b) in all.iter().enumerate() {
        if b.lang == "sh" && !b.skip {
            let out = mpi_env(Command::new("bash").args(["-e", "-o", "pipefail", "-c", &b.text]))
                .current_dir(&dir)
                .env("POROPLAST_BIN", dir.join("target/release/poroplast"))
                .env("OMPI_MCA_rmaps_base_oversubscribe", "1")
                .output()
                .expect("bash");
            printed = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
            assert!(out.status.success(), "tutorial block {i} failed:\n{}\n--- printed:\n{printed}", b.text);
        } else if b.lang == "text" && i > 0 && all[i - 1].lang == "sh" && !all[i - 1].skip {
            for want in b.text.lines().map(str::trim).filter(|l| !l.is_empty() && *l != "...") {
                assert!(
                    printed.lines().any(|l| l.trim() == want),
                    "the tutorial says the commands print\n  {want}\nbut they printed:\n{printed}"
                );
            }
        }
    }
}

#[test]
fn blocks_are_read_with_their_skip_marks() {
    let md = "text\n<!-- tutorial test: skip (set-up) -->\n\n```sh\nsetup\n```\n\n```sh\nrun\n```\n```text\nout\n```\n";
    let b = blocks(md);
    assert_eq!(b.len(), 3);
    assert!(b[0].skip && b[0].text == "setup\n" && b[0].lang == "sh");
    assert!(!b[1].skip && b[1].text == "run\n");
    assert!(b[2].lang == "text" && b[2].text == "out\n");
}
