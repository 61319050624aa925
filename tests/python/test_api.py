#!/usr/bin/python3
"""The Python module (src/python/) against the CLI: the same answers, the same errors.

Run by ctest (tests/CMakeLists.txt) with Debian's python, PYTHONPATH the build tree's python/ and
LIFTOFF_CLI the liftoff executable beside it; a test class per ctest test:
    /usr/bin/python3 tests/python/test_api.py CliAgreement

The module calls the CLI's own library functions, so its answers are the CLI's bit for bit: the JSON
is compared key by key with ==, times excepted (nlohmann writes the shortest representation that
reads back to the same double, so equal text means equal doubles).
"""
import gc
import json
import math
import os
import pathlib
import subprocess
import sys
import tempfile
import threading
import tomllib
import unittest

import numpy

import liftoff

SOURCE = pathlib.Path(os.environ.get("LIFTOFF_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
CLI = os.environ.get("LIFTOFF_CLI", str(SOURCE / "build/src/liftoff"))
SCENES = sorted((SOURCE / "verification/scenes").rglob("*.toml"))
SEED = "verification/scenes/seed_arch_pinned.toml"


def cli(*args):
    """liftoff ARGS run from the source directory: (exit code, stdout, stderr)."""
    p = subprocess.run([CLI, *args], cwd=SOURCE, capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def without_times(value):
    """The JSON without the run's times (and the CLI's exit code, compared on its own)."""
    if isinstance(value, dict):
        return {k: without_times(v) for k, v in value.items() if k not in ("time_s", "exit_code")}
    if isinstance(value, list):
        return [without_times(v) for v in value]
    return value


def differences(a, b, where=""):
    """Where two JSON values differ: [(path, a, b)]; floats compared with ==."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = [(f"{where}.{k}", a.get(k, "<absent>"), b.get(k, "<absent>")) for k in set(a) ^ set(b)]
        for k in set(a) & set(b):
            out += differences(a[k], b[k], f"{where}.{k}")
        return out
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        return [d for i, (x, y) in enumerate(zip(a, b)) for d in differences(x, y, f"{where}[{i}]")]
    return [] if a == b else [(where, a, b)]


class CliAgreement(unittest.TestCase):
    """Every shipped scene: liftoff.solve gives `liftoff solve --json`, or raises what the CLI refuses with."""

    def test_every_shipped_scene(self):
        self.assertGreater(len(SCENES), 20)
        os.chdir(SOURCE)
        for scene in SCENES:
            name = str(scene.relative_to(SOURCE))
            with self.subTest(scene=name):
                code, out, err = cli("solve", name, "--json")
                expected = json.loads(out)
                if code == liftoff.InputError.exit_code:
                    with self.assertRaises(liftoff.InputError) as refused:
                        liftoff.solve(name)
                    self.assertEqual("liftoff: " + str(refused.exception), err.strip())
                    continue
                result = liftoff.solve(name, check=False)
                self.assertEqual(result.exit_code, code, err)
                self.assertEqual(differences(without_times(result.json), without_times(expected)), [])
                # With check (the default) an answer that is not solved raises the CLI's message.
                if code != 0:
                    with self.assertRaises(liftoff.SolverFailure) as failed:
                        liftoff.solve(name)
                    self.assertEqual(failed.exception.exit_code, code)
                    self.assertEqual("liftoff: " + str(failed.exception), err.strip().splitlines()[0])

    def test_options_are_the_cli_options(self):
        os.chdir(SOURCE)
        code, out, _ = cli("solve", SEED, "--json", "--method", "dual", "--elements", "120")
        self.assertEqual(code, 0)
        result = liftoff.solve(SEED, method="dual", elements=120)
        self.assertEqual(result.elements, 120)
        self.assertEqual(differences(without_times(result.json), without_times(json.loads(out))), [])
        # fields=False is the CLI without a file of fields, fields=True (the default) the CLI with one:
        # with a tolerance their design values differ (the extremes of different samples).
        code, out, _ = cli("solve", SEED, "--json", "--tolerance", "1e-3")
        result = liftoff.solve(SEED, tolerance=1e-3, fields=False)
        self.assertEqual(differences(without_times(result.json), without_times(json.loads(out))), [])
        with tempfile.TemporaryDirectory() as d:
            code, out, _ = cli("solve", SEED, "--json", "--tolerance", "1e-3", "--output", str(pathlib.Path(d) / "f.h5"))
        result = liftoff.solve(SEED, tolerance=1e-3)
        self.assertEqual(differences(without_times(result.json), without_times(json.loads(out))), [])

    def test_method_all_gives_every_method(self):
        os.chdir(SOURCE)
        # The seed arch, and a sleeper held by the ballast alone (the dual form refused).
        for scene in (SEED, "verification/scenes/engineering/sleeper_centre_bound.toml"):
            code, out, _ = cli("solve", scene, "--json", "--method", "all")
            results = liftoff.solve(scene, method="all", check=False)
            expected = json.loads(out)["methods"]
            self.assertEqual([r.method for r in results], [m["method"] for m in expected])
            for r, m in zip(results, expected):
                self.assertEqual(differences(without_times(r.json), without_times(m)), [])
        self.assertIn("refused", [r.termination for r in results])

    def test_trace_and_sweep(self):
        os.chdir(SOURCE)
        name = "verification/scenes/engineering/pipeline_500m_uplift.toml"
        code, out, _ = cli("trace", name, "--json", "--elements", "400")
        traced = liftoff.trace(name, elements=400, check=False)
        self.assertEqual(differences(without_times(traced.json), without_times(json.loads(out))), [])
        steps = traced.steps()
        self.assertEqual(len(steps["lambda"]), len(traced.json["paths"][0]["steps"]))
        self.assertFalse(steps["lambda"].flags.owndata)  # a strided view of the steps
        self.assertEqual(steps["lambda"].tolist(), [s["lambda"] for s in traced.json["paths"][0]["steps"]])
        # A sweep: the CLI's CSV but for its time column.
        code, out, _ = cli("sweep", SEED, "--set", "foundation.nondimensional_k=1e4,1e5,1e6", "--set",
                           "loads[0].value=0.05,0.1", "--jobs", "2")
        swept = liftoff.sweep(SEED, {"foundation.nondimensional_k": [1e4, 1e5, 1e6], "loads[0].value": "0.05,0.1"},
                              jobs=2)
        self.assertEqual(code, 0)

        def untimed(csv):
            rows = [line.split(",") for line in csv.splitlines()]
            column = rows[0].index("time_s")
            return [row[:column] + row[column + 1:] for row in rows]
        self.assertEqual(untimed(swept.csv), untimed(out))
        self.assertEqual(swept.values.shape, (6, 2))
        self.assertEqual(swept.values[1].tolist(), [1e4, 0.1])  # the last key varies fastest
        # The last case (k = 1e6, P = 0.1) is the seed scene itself.
        case = swept.cases[5]["reports"][0]
        seed = liftoff.solve(SEED, fields=False)
        self.assertEqual((case.contact_regions, case.w_max), (seed.contact_regions, seed.w_max))


class Scenes(unittest.TestCase):
    """A scene as a file, TOML text or a dict: one answer."""

    def test_text_and_dict_give_the_file_answer(self):
        os.chdir(SOURCE)
        text = (SOURCE / SEED).read_text()
        scene = tomllib.loads(text)
        from_file = without_times(liftoff.solve(SEED).json)
        for source, name in ((text, "scene string"), (scene, "scene dict"), (pathlib.Path(SEED), SEED)):
            r = without_times(liftoff.solve(source).json)
            self.assertEqual(r.pop("scene"), name)
            self.assertEqual(differences(r, {k: v for k, v in from_file.items() if k != "scene"}), [])

    def test_fields_are_read_only_views(self):
        r = liftoff.solve(SOURCE / SEED)
        self.assertEqual(len(r.positions), len(r.w))
        self.assertGreater(len(r.w), 100)
        for name in ("positions", "w", "u", "rotation", "M", "V", "N", "reaction"):
            a = getattr(r, name)
            self.assertFalse(a.flags.owndata, name)
            self.assertFalse(a.flags.writeable, name)
        self.assertTrue(numpy.shares_memory(r.w, r.fields["w"]))  # the report's own vector, twice
        self.assertTrue(numpy.shares_memory(r.M, r.fields["bending_moment"]))
        w, values = r.w, r.w.copy()
        del r  # the view keeps the answer alive
        gc.collect()
        liftoff.solve(SOURCE / SEED, elements=400)  # memory a freed answer would have been reused for
        self.assertTrue(numpy.array_equal(w, values))

    def test_answer_in_the_users_terms(self):
        # The seed arch (pinned ends): a contact half-angle of 3.758 degrees (the scene's comment).
        r = liftoff.solve(SOURCE / SEED)
        (begin, end), = r.contact_regions
        self.assertAlmostEqual(end, 3.758, delta=0.01)
        self.assertAlmostEqual(begin, -end, delta=1e-9)
        self.assertTrue(r.certified)
        self.assertEqual(r.termination, r.json["termination"])


class Errors(unittest.TestCase):
    """Bad input: the exception of its kind, the CLI's message naming the key, the CLI's exit code."""

    def refused(self, error, scene, *names, **options):
        with self.assertRaises(error) as caught:
            liftoff.solve(scene, **options)
        for n in names:
            self.assertIn(n, str(caught.exception))
        self.assertEqual(len(str(caught.exception).splitlines()), 1)
        return caught.exception

    def test_unknown_key(self):
        text = (SOURCE / SEED).read_text().replace("\nEI = 1.4\n", "\nEI = 1.4\nstifness = 2\n")
        e = self.refused(liftoff.InputError, text, "structure.stifness")
        self.assertIsInstance(e, ValueError)
        self.assertEqual(e.exit_code, 2)
        with tempfile.TemporaryDirectory() as d:
            path = pathlib.Path(d) / "typo.toml"
            path.write_text(text)
            code, _, err = cli("solve", str(path))
            self.assertEqual(code, 2)
            e = self.refused(liftoff.InputError, str(path), "structure.stifness")
            self.assertEqual("liftoff: " + str(e), err.strip())
        scene = tomllib.loads((SOURCE / SEED).read_text())
        scene["foundation"]["modulas"] = 3.0
        self.refused(liftoff.InputError, scene, "foundation.modulas", "scene dict")

    def test_bad_value(self):
        text = (SOURCE / SEED).read_text().replace("\nEI = 1.4\n", "\nEI = -1.4\n")
        self.refused(liftoff.InputError, text, "structure.EI")
        scene = tomllib.loads((SOURCE / SEED).read_text())
        scene["structure"]["EI"] = [1.4]
        self.refused(liftoff.InputError, scene, "structure.EI")
        scene["structure"]["EI"] = object()
        self.refused(liftoff.InputError, scene, "structure.EI")
        self.refused(liftoff.InputError, SOURCE / SEED, "method", method="newton")
        self.refused(liftoff.InputError, SOURCE / SEED, "tolerance", tolerance=0.5)
        self.refused(liftoff.InputError, SOURCE / SEED, "elements", elements=0)
        self.refused(liftoff.InputError, SOURCE / SEED, "modes", modes="many")

    def test_missing_file(self):
        e = self.refused(liftoff.InputError, "no/such/scene.toml", "no/such/scene.toml", "cannot read")
        code, _, err = cli("solve", "--json", str(SOURCE / SEED))  # the CLI checks the path itself (CLI11)
        self.assertEqual(code, 0)
        self.assertIn("No such file", str(e))

    def test_mechanism(self):
        # An arch on rollers turned by a moment: its rigid rotation is free (tests/contact/contact_solver_test.cpp).
        scene = tomllib.loads((SOURCE / "verification/scenes/seed_arch_roller.toml").read_text())
        scene["loads"].append({"kind": "moment", "at": 2.0, "value": 0.01})
        scene["solve"]["method"] = "dual"
        e = self.refused(liftoff.MechanismError, scene, "scene dict")
        self.assertIsInstance(e, liftoff.InputError)
        with tempfile.TemporaryDirectory() as d:
            path = pathlib.Path(d) / "mechanism.toml"
            path.write_text(((SOURCE / "verification/scenes/seed_arch_roller.toml").read_text()
                             .replace('method = "auto"', 'method = "dual"')
                             + '\n[[loads]]\nkind = "moment"\nat = 2.0\nvalue = 0.01\n'))
            code, _, err = cli("solve", str(path))
            with self.assertRaises(liftoff.MechanismError) as caught:
                liftoff.solve(path)
            self.assertEqual(code, liftoff.MechanismError.exit_code)
            self.assertEqual("liftoff: " + str(caught.exception), err.strip())


class Threads(unittest.TestCase):
    """The GIL is released while the library solves: two threads solve at once, each its own answer."""

    def test_two_threads(self):
        scenes = [SOURCE / SEED, SOURCE / "verification/scenes/engineering/sleeper_b70_ballast.toml"]
        serial = [without_times(liftoff.solve(s).json) for s in scenes]
        answers, errors = [None, None], []

        def run(i):
            try:
                for _ in range(3):
                    answers[i] = without_times(liftoff.solve(scenes[i]).json)
            except Exception as e:  # noqa: BLE001 - reported below
                errors.append(e)
        threads = [threading.Thread(target=run, args=(i,)) for i in range(2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        self.assertEqual(errors, [])
        self.assertEqual(answers, serial)


class Plot(unittest.TestCase):
    def test_plot_writes_a_picture(self):
        with tempfile.TemporaryDirectory() as d:
            figure = liftoff.plot(liftoff.solve(SOURCE / SEED), pathlib.Path(d) / "seed.png")
            self.assertEqual(len(figure.axes), 4)
            self.assertGreater((pathlib.Path(d) / "seed.png").stat().st_size, 10_000)
        with self.assertRaises(TypeError):
            liftoff.plot(42)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1] + sys.argv[1:], verbosity=2)
