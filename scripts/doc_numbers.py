#!/usr/bin/env python3
"""The docs' numbers and their sources (poroplast_tools/doc_numbers.py says how a number is
bound or listed).

    python3 scripts/doc_numbers.py --write docs/reproduction.md  # render its bound numbers from their sources
    python3 scripts/doc_numbers.py --check                       # every page: what is stale, unbound or unlisted
    python3 scripts/doc_numbers.py --free docs/studies.md        # its unbound, unlisted numbers, with the
                                                                 # cells that equal them (candidate bindings)
                                                                 # and a stub for the list
    python3 scripts/doc_numbers.py --mutate                      # change each bound number by one unit in its
                                                                 # last digit: does the check fail every time?
"""
import argparse
import json
import sys
from pathlib import Path

from poroplast_tools import doc_numbers as dn

ROOT = Path(__file__).resolve().parent.parent


def page_name(path):
    p = Path(path).resolve()
    try:
        return str(p.relative_to(ROOT))
    except ValueError:
        sys.exit(f"{path}: not a file of this repository")


def read(name):
    if not (ROOT / name).exists():
        sys.exit(f"{name}: no such file")
    return dn.read_page(name)


def check(pages):
    listed, sources = dn.load_list()
    bad = 0
    for name in pages:
        for p in dn.problems(read(name), listed.get(name, []), sources):
            print(f"{name}: {p}")
            bad += 1
    return bad


def free(name):
    text = read(name)
    listed, _ = dn.load_list()
    cells = dn._cells()
    lines = text.split("\n")
    blanked = dn.blank(text).split("\n")
    for i, nums, have in dn.unlisted(text, listed.get(name, [])):
        print(f"line {i}: {lines[i - 1].strip()[:160]}")
        if have is not None:
            print(f"  the list has {have}")
        row = lines[i - 1].lstrip().startswith("|")
        for m in dn.TOKEN.finditer(blanked[i - 1]):
            n = m.group(0)
            sign = lines[i - 1][m.start() - 1:m.start()] if m.start() else ""
            signed = (sign if sign in ("+", "−", "-") else "") + n
            c = [x.replace("|", "\\|") if row else x for x in dn.candidates(signed, cells)]
            shown = "; ".join(f"<!-- = {x} -->" for x in c[:4]) + (f" (+{len(c) - 4} more)" if len(c) > 4 else "")
            print(f"  {signed}: {shown or 'no cell of a committed CSV'}")
        at = json.dumps(dn.plain(lines[i - 1]).strip()[:40], ensure_ascii=False)
        print(f'  [[line]]\n  page = "{name}"\n  at = {at}\n  numbers = {json.dumps(nums, ensure_ascii=False)}\n  source = "?"')


def mutate(pages):
    listed, sources = dn.load_list()
    total = failed = 0
    for name in pages:
        for line, printed, text in dn.mutants(read(name)):
            total += 1
            if dn.stale(text):
                failed += 1
            else:
                print(f"{name}:{line}: {printed} -> {dn.nudge(printed)} is not caught")
    print(f"{failed} of {total} bound numbers fail when changed by one unit in the last digit")
    return total - failed


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--write", metavar="FILE", help="render FILE's bound numbers from their sources")
    ap.add_argument("--check", nargs="*", metavar="FILE", help=f"check FILEs (default: {' '.join(dn.PAGES)})")
    ap.add_argument("--free", metavar="FILE", help="list FILE's numbers that are neither bound nor listed")
    ap.add_argument("--mutate", nargs="*", metavar="FILE", help="the test of the test, over FILEs (default: all pages)")
    a = ap.parse_args()
    if a.write:
        name = page_name(a.write)
        try:
            text = dn.write(read(name))
        except (KeyError, ValueError, ZeroDivisionError) as e:
            sys.exit(f"{name}: a bound number has no value: {e}")
        dn.write_page(name, text)
        print(f"{name}: {len(dn.bound(text))} bound numbers written")
    elif a.free:
        free(page_name(a.free))
    elif a.mutate is not None:
        sys.exit(1 if mutate([page_name(p) for p in a.mutate] or dn.PAGES) else 0)
    elif a.check is not None:
        sys.exit(1 if check([page_name(p) for p in a.check] or dn.PAGES) else 0)
    else:
        ap.print_help()


if __name__ == "__main__":
    main()
