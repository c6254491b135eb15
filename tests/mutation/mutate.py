#!/usr/bin/env python3
"""Mutation testing of the test suite: does a small, plausible bug in the code make a test fail?

Each entry of mutations.json names a file, an exact piece of it (`old`, found exactly once), its replacement
(`new`) and the test executables of the module (`tests`). For each: apply it, build those tests, run them, restore
the file (also on an error or Ctrl-C). A mutation no test kills is a test that cannot fail there: either a gap to
close with a test, or an equivalent change (docs/BENCHMARKS.md, sixteenth and seventeenth rounds, says which).

  tests/mutation/mutate.py [--build DIR] [--only NAME_PREFIX ...] [--list FILE]
  tests/mutation/mutate.py --check [--list FILE]

--check builds and runs nothing: it checks that every entry still applies (its text found exactly once, a
distinct first word, test executables that exist as tests/*/NAME.cpp). It is a ctest (MutationList.Check), so an
edit that reformats a quoted line cannot leave the list stale unnoticed.

Run from anywhere in a configured checkout (default build directory: build/). Files with uncommitted changes are
skipped, so a run never loses work. Prints one line per mutation: KILLED by which tests (the count of failed test
cases; 0 for a crash or timeout), SURVIVED, or why it was skipped.
"""
import argparse
import json
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]


def run_one(m, build, timeout):
    path = ROOT / m["file"]
    if subprocess.run(["git", "diff", "--quiet", "--", m["file"]], cwd=ROOT).returncode != 0:
        return "skipped (the file has uncommitted changes)"
    src = path.read_text()
    if src.count(m["old"]) != 1:
        return f"skipped (the text is found {src.count(m['old'])} times, not once)"
    path.write_text(src.replace(m["old"], m["new"]))
    try:
        b = subprocess.run(["cmake", "--build", str(build), "-j2", "--target", *m["tests"]], cwd=ROOT,
                           capture_output=True, text=True)
        if b.returncode != 0:
            return "skipped (does not build)"
        failed = []
        for t in m["tests"]:
            try:
                r = subprocess.run([str(build / "tests" / t), "--gtest_brief=1"], capture_output=True, text=True,
                                   timeout=timeout)
            except subprocess.TimeoutExpired:
                failed.append(f"{t}(timeout)")
                continue
            if r.returncode != 0:
                cases = {l for l in r.stdout.splitlines() if l.startswith("[  FAILED  ]") and "." in l}
                failed.append(f"{t}({len(cases)})")
        return "KILLED by " + ", ".join(failed) if failed else "SURVIVED"
    finally:
        path.write_text(src)


def check(mutations):
    """The problems that would make entries skip or mislead, one line each; empty when the list is sound."""
    problems, first_words = [], {}
    tests = {p.stem for p in (ROOT / "tests").glob("*/test_*.cpp")}
    for m in mutations:
        name = m.get("name", "")
        word = name.split()[0] if name.split() else ""
        if word in first_words:
            problems.append(f"{name}: first word '{word}' also names '{first_words[word]}'")
        first_words.setdefault(word, name)
        path = ROOT / m["file"]
        count = path.read_text().count(m["old"]) if path.is_file() else -1
        if count != 1:
            problems.append(f"{name}: {m['file']}: the text is found {count} times, not once"
                            if count >= 0 else f"{name}: {m['file']}: no such file")
        if m["old"] == m["new"]:
            problems.append(f"{name}: the replacement changes nothing")
        missing = [t for t in m["tests"] if t not in tests]
        if not m["tests"] or missing:
            problems.append(f"{name}: no test executable {', '.join(missing) or '(none listed)'}")
    return problems


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(ROOT / "build"), help="configured build directory (default build/)")
    ap.add_argument("--only", nargs="*", default=[], help="run the mutations whose names start with these")
    ap.add_argument("--list", default=str(pathlib.Path(__file__).with_name("mutations.json")))
    ap.add_argument("--check", action="store_true", help="only check that every entry applies (see above)")
    ap.add_argument("--timeout", type=float, default=240.0, help="seconds per test executable (a hang kills)")
    args = ap.parse_args()
    mutations = json.loads(pathlib.Path(args.list).read_text())
    if args.only:
        mutations = [m for m in mutations if any(m["name"].startswith(p) for p in args.only)]
    if args.check:
        problems = check(mutations)
        for p in problems:
            print(p)
        print(f"{len(mutations)} mutations, {len(problems)} problems")
        return 1 if problems else 0
    survived = 0
    try:
        for m in mutations:
            outcome = run_one(m, pathlib.Path(args.build), args.timeout)
            survived += outcome == "SURVIVED"
            print(f"{m['name']}: {outcome}", flush=True)
    finally:  # leave the build matching the sources
        subprocess.run(["cmake", "--build", args.build, "-j2"], cwd=ROOT, capture_output=True)
    print(f"{len(mutations)} mutations, {survived} survived")
    return 0


if __name__ == "__main__":
    sys.exit(main())
