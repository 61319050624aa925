#!/usr/bin/python3
"""Comparison harness: every scene in verification/scenes/, liftoff's methods against each other
and against independent references, with tolerances from each side's own error estimate.

    /usr/bin/python3 verification/compare.py --liftoff build/src/liftoff \\
        --closed-form build/verification/closed_form_reference [--dolfinx] [--markdown FILE]

For every contact limit each method gives a value and an error estimate:
  - FE dual: on meshes n/2, n and 2n; limits converge at about h^2 but oscillate with where the
    limit falls in its element, so the error of the 2n result is taken as its whole change from n
    (not a third of it, as Richardson would for a monotone sequence);
  - FE primal: on mesh n; the same discrete solution as the dual on that mesh (to round-off), so
    it carries the dual's estimate for mesh n (its change from n/2);
  - FE fast: where the dual form refuses (a member only the foundation holds), the sparse active
    set on meshes n/2, n and 2n, estimated as the dual;
  - Ritz: automatic modes, its own estimate (the last change of the limits with N);
  - closed form (beams): exact up to its Newton tolerance (1e-10 of the length);
  - dolfinx penalty model (with --dolfinx): its refinement study's estimate.
Two methods agree when |a - b| <= 3 (e_a + e_b) + 1e-12 * length. A table is printed (and
written as Markdown with --markdown); the exit code is 1 if any pair disagrees.

Scenes: every *.toml in --scenes (the seed scenes) and in --engineering (default
verification/scenes/engineering/; --engineering '' to skip). The closed form is asked for every
beam and answers where it applies (foundation pieces, voids, gaps, K_t and piecewise-linear loads
included); a scene it does not cover (arches, interior supports, a modulus varying within a piece)
is left out of its column, not a failure. liftoff refusing a scene is reported as
"liftoff <method>: refused (exit N): message" and the references are still compared with each
other: exit 2 (liftoff cannot read the scene, e.g. an issue 12 key it does not read yet) fails
the run unless --allow-unread (but the Ritz model refusing, by key, an input its moving-boundary
formulation does not hold, "the Ritz model cannot take this scene", is reported); exit 3 (a reasoned refusal) fails for the seed scenes and is only
reported for the engineering ones (verification/engineering_corpus.py asserts which of those are
expected).
"""
import argparse
import glob
import json
import os
import subprocess
import sys
import tempfile
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))


class Refused(str):
    """A failure message that is liftoff's refusal (exit 2 or 3), with its exit code."""

    def __new__(cls, text, code):
        obj = str.__new__(cls, text)
        obj.code = code
        return obj


def run_json(command):
    p = subprocess.run(command, capture_output=True, text=True)
    if p.returncode != 0:
        message = p.stderr.strip()
        try:   # exit 3 carries one JSON object with the reason on stdout
            message = json.loads(p.stdout).get("message") or message
        except (json.JSONDecodeError, AttributeError):
            message = message or p.stdout.strip()
        message = (message.splitlines() or [f"exit {p.returncode}"])[-1]
        if p.returncode in (2, 3):
            return None, Refused(f"refused (exit {p.returncode}): {message}", p.returncode)
        return None, f"exit {p.returncode}: {message}"
    return json.loads(p.stdout), None


def limits(result):
    return [x for region in result["contact_regions"] for x in region]


def fe_three_meshes(liftoff, scene, method, elements):
    """limits on n/2, n, 2n; the error of the 2n result taken as its change from n."""
    runs = [run_json([liftoff, "solve", scene, "--method", method, "--elements", str(n), "--json"])
            for n in (elements // 2, elements, 2 * elements)]
    for obj, err in runs:
        if obj is None:
            return None, None, err
    coarse, mid, fine = (limits(obj) for obj, _ in runs)
    if not len(coarse) == len(mid) == len(fine):
        return None, None, (f"the number of contact limits changes between {elements // 2}, {elements} and "
                            f"{2 * elements} elements ({len(coarse)}, {len(mid)}, {len(fine)})")
    return (fine, [abs(f - m) for f, m in zip(fine, mid)], f"{2 * elements} el."), \
        [abs(m - c) for m, c in zip(mid, coarse)], None


def liftoff_results(liftoff, scene, elements):
    out = {}
    dual, mesh_estimate, err = fe_three_meshes(liftoff, scene, "dual", elements)
    if dual:
        out["FE dual"] = dual
        primal, err4 = run_json([liftoff, "solve", scene, "--method", "primal", "--elements", str(elements), "--json"])
        if primal:
            out["FE primal"] = (limits(primal), mesh_estimate, f"{elements} el.")
    else:
        out["FE dual"] = (None, err, "")
        if isinstance(err, Refused) and err.code == 3:
            # the dual form refuses a member only the foundation holds: the same discrete
            # problem by the sparse active set (fast), which must answer everywhere
            fast, _, err4 = fe_three_meshes(liftoff, scene, "fast", elements)
            out["FE fast"] = fast or (None, err4, "")
    ritz, err = run_json([liftoff, "solve", scene, "--method", "ritz", "--json"])
    if ritz:
        estimate = ritz.get("estimated_limit_error", 0.0)
        out["Ritz"] = (limits(ritz), [estimate] * len(limits(ritz)), f"{ritz['modes']} modes")
    else:
        out["Ritz"] = (None, err, "")
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--liftoff", required=True)
    parser.add_argument("--closed-form", required=True)
    parser.add_argument("--dolfinx", action="store_true", help="also run verification/dolfinx/penalty_reference.py")
    parser.add_argument("--scenes", default=os.path.join(HERE, "scenes"))
    parser.add_argument("--engineering", default=os.path.join(HERE, "scenes", "engineering"),
                        help="a second folder of scenes whose reasoned refusals (exit 3) are reported, not failures "
                             "('' to skip)")
    parser.add_argument("--allow-unread", action="store_true",
                        help="liftoff refusing to read a scene (exit 2) is reported, not a failure")
    parser.add_argument("--markdown", default=None)
    parser.add_argument("--elements", type=int, default=100, help="the FE mesh n (dual also on n/2 and 2n)")
    args = parser.parse_args()

    rows, failures, refusals = [], 0, 0
    scenes = [(s, False) for s in sorted(glob.glob(os.path.join(args.scenes, "*.toml")))]
    if args.engineering:
        scenes += [(s, True) for s in sorted(glob.glob(os.path.join(args.engineering, "*.toml")))]
    for scene, engineering in scenes:
        name = ("engineering/" if engineering else "") + os.path.basename(scene)[:-5]
        with open(scene, "rb") as f:
            description = tomllib.load(f)
        arch = description["structure"]["kind"] == "arch"
        length = 2 * description["structure"]["half_angle_deg"] if arch else description["structure"]["length"]
        # engineering scenes on their own mesh (real members: beta L up to 62)
        n = description.get("solve", {}).get("elements", args.elements) if engineering else args.elements
        results = liftoff_results(args.liftoff, scene, n)
        if not arch:    # exit 2: a scene the closed form does not cover (not a failure)
            reference, err = run_json([args.closed_form, scene])
            if reference:
                results["closed form"] = (limits(reference), [1e-10 * length] * len(limits(reference)), "exact")
            elif not isinstance(err, Refused) or err.code != 2:
                results["closed form"] = (None, err, "")
        if args.dolfinx:
            with tempfile.TemporaryDirectory() as tmp:
                out = os.path.join(tmp, "d.json")
                p = subprocess.run(["/usr/bin/python3", os.path.join(HERE, "dolfinx", "penalty_reference.py"), scene,
                                    "--refine", "--json", out], capture_output=True, text=True)
                if p.returncode == 0:
                    with open(out) as f:
                        d = json.load(f)
                    results["dolfinx"] = (limits(d), [d.get("estimated_limit_error", 0.0)] * len(limits(d)),
                                          f"{d['elements']} el.")
                else:
                    results["dolfinx"] = (None, p.stderr.strip().splitlines()[-1:] or ["failed"], "")

        methods = [m for m, (values, _, _) in results.items() if values is not None]
        for m, (values, message, _) in results.items():
            if values is None:
                liftoff = m in ("FE dual", "FE primal", "FE fast", "Ritz")
                if liftoff and isinstance(message, Refused) and (
                        (message.code == 2 and args.allow_unread) or (message.code == 3 and engineering)
                        or (m == "Ritz" and message.code == 2 and "the Ritz model cannot take this scene" in str(message))):
                    print(f"{name}: liftoff {m}: {message}")
                    refusals += 1
                    continue
                print(f"{name}: {'liftoff ' if liftoff else ''}{m} failed: {message}")
                failures += 1
        if len(methods) < 2:
            print(f"{name}: fewer than two answers, nothing to compare")
            continue
        counts = {len(results[m][0]) for m in methods}
        if len(counts) != 1:
            print(f"{name}: methods disagree on the number of contact limits: "
                  + ", ".join(f"{m} {len(results[m][0])}" for m in methods))
            failures += 1
            continue
        for i in range(counts.pop()):
            # The pair that uses most of its allowance decides.
            worst, allowed_at_worst = None, None
            for a in methods:
                for b in methods:
                    va, ea = results[a][0][i], results[a][1][i]
                    vb, eb = results[b][0][i], results[b][1][i]
                    difference, allowed = abs(va - vb), 3 * (ea + eb) + 1e-12 * length
                    if worst is None or difference / allowed > worst / allowed_at_worst:
                        worst, allowed_at_worst = difference, allowed
            ok = worst <= allowed_at_worst
            failures += not ok
            cells = [f"{results[m][0][i]:.9f} ± {results[m][1][i]:.1e}" for m in methods]
            rows.append((name, i + 1, methods, cells, worst, allowed_at_worst, ok))

    header_methods = ["FE dual", "FE primal", "FE fast", "Ritz", "closed form", "dolfinx"]
    lines = ["| scene | limit | " + " | ".join(header_methods) + " | largest difference | allowed | |",
             "|---|---|" + "---|" * len(header_methods) + "---|---|---|"]
    for name, i, methods, cells, worst, allowed, ok in rows:
        by_method = dict(zip(methods, cells))
        lines.append(f"| {name} | {i} | " + " | ".join(by_method.get(m, "-") for m in header_methods)
                     + f" | {worst:.1e} | {allowed:.1e} | {'ok' if ok else 'DISAGREE'} |")
    table = "\n".join(lines)
    print(table)
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(table + "\n")
    print(f"{len(rows)} limits compared, {failures} failures, {refusals} liftoff refusals reported")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
