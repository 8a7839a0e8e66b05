#!/usr/bin/env python3
"""The paper's claims table: every statement of Di Stefano et al. (2022) about its simulations,
one row each (data/claims.csv), with our converged numbers (data/references.csv) and the
verdict of the written rule.

    python3 scripts/claims.py                              # print the table
    python3 scripts/claims.py --write docs/reproduction.md # replace the claims table, the (40a)
                                                           # table (data/hypothesis_40a*.csv) and the
                                                           # tables of poroplast_tools/doc_tables there,
                                                           # and its bound numbers (doc_numbers.py --write)
    python3 scripts/claims.py --rule                       # print the verdict rule
"""
import argparse
from pathlib import Path

from poroplast_tools import claims, doc_numbers, doc_tables, hypothesis


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--write", metavar="FILE", help="replace the generated table in FILE (between its markers)")
    ap.add_argument("--rule", action="store_true", help="print the verdict rule")
    a = ap.parse_args()
    if a.rule:
        print(claims.RULE)
        return
    generated = claims.table()
    if a.write:
        path = Path(a.write)
        text = claims.replace_in(path.read_text(encoding="utf-8"), generated)
        text = claims.replace_in(text, hypothesis.table(), hypothesis.BEGIN, hypothesis.END)
        try:
            text = doc_numbers.write(doc_tables.write_all(text, claims.replace_in))
        except (KeyError, ValueError, ZeroDivisionError) as e:
            raise SystemExit(f"{path}: a bound number has no value: {e} (python3 scripts/doc_numbers.py --check {path})")
        path.write_text(text, encoding="utf-8")
        print(f"{path}: the claims table, the (40a) table, the other generated tables and the bound numbers written")
    else:
        print(generated, end="")


if __name__ == "__main__":
    main()
