"""The Python module against the command line: the same scene gives the same history, a scene
given as a dict runs as its file does, overrides of every Python type arrive, and errors arrive
as exceptions carrying the scene error's text. Run by ctest with PYTHONPATH=build/python."""

import os
import subprocess
import tempfile
import tomllib
import unittest

import numpy as np

import ifsim

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
IFSIM = os.environ.get("IFSIM_EXECUTABLE", os.path.join(ROOT, "build", "ifsim"))
SCENE = os.path.join(ROOT, "scenes", "simple-shear-cnl-stutz.toml")
FAST = {"interface.subincrement": "adaptive", "stage.1.steps": 200}


def cli_history(scene, sets):
    with tempfile.TemporaryDirectory() as out:
        args = [IFSIM, "run", scene, "--out", out, "-q", "--threads", "1"]
        for s in sets:
            args += ["--set", s]
        subprocess.run(args, check=True)
        data = np.genfromtxt(os.path.join(out, "history.csv"), delimiter=",", names=True)
    return {name: data[name] for name in data.dtype.names}


class ModuleRuns(unittest.TestCase):
    def test_same_history_as_the_command_line(self):
        r = ifsim.run(SCENE, set=dict(FAST, **{"interface.roughness": 0.9}), threads=1)
        self.assertTrue(r.ok)
        cli = cli_history(SCENE, ["interface.subincrement=\"adaptive\"", "stage.1.steps=200",
                                  "interface.roughness=0.9"])
        self.assertEqual(set(cli), set(r.history))
        for name, values in cli.items():
            np.testing.assert_array_equal(r[name], values, err_msg=name)
        self.assertEqual(len(r["t_t1"]), 201)
        self.assertAlmostEqual(r.summary["results"]["peak_shear_stress"], r["t_t1"].max())
        self.assertIsNone(r.out)  # a temporary folder, gone

    def test_a_scene_as_a_dict_runs_as_its_file(self):
        with open(SCENE, "rb") as f:
            scene = tomllib.load(f)
        scene["interface"]["roughness"] = np.float64(0.8)  # NumPy values are taken too
        scene["stage"][0]["steps"] = np.int64(200)
        scene["interface"]["subincrement"] = "adaptive"
        from_dict = ifsim.run(scene, threads=1)
        from_file = ifsim.run(SCENE, threads=1, set=["interface.roughness=0.8",
                                                     "stage.1.steps=200",
                                                     "interface.subincrement=\"adaptive\""])
        for name in from_file.history:
            np.testing.assert_array_equal(from_dict[name], from_file[name], err_msg=name)

    def test_out_keeps_the_run_folder(self):
        with tempfile.TemporaryDirectory() as out:
            r = ifsim.run(SCENE, out=out, set=FAST)
            self.assertEqual(r.out, out)
            for name in ("history.csv", "summary.json", "scene.toml"):
                self.assertTrue(os.path.exists(os.path.join(out, name)), name)

    def test_scene_errors_are_exceptions_with_the_key(self):
        with self.assertRaises(ifsim.SceneError) as e:
            ifsim.run(SCENE, set={"interface.roughness": 1.5})
        self.assertIn("interface.roughness", str(e.exception))
        self.assertIn("(0, 1]", str(e.exception))
        with self.assertRaises(ifsim.SceneError) as e:
            ifsim.run({"kind": "element-test", "material": {"model": "no-such-model"}})
        self.assertIn("material.model", str(e.exception))
        with self.assertRaises(TypeError):
            ifsim.run({"kind": "element-test", "material": {"model": object()}})

    def test_a_failed_run_raises_with_its_rows(self):
        # Stutz, kappa = 1, d_s = 3 mm, adaptive sub-increments: the step Newton stops before
        # 2 mm (docs/reliability.md); the rows up to there come with the exception.
        failing = {"interface.roughness": 1.0, "interface.subincrement": "adaptive"}
        with self.assertRaises(ifsim.RunFailed) as e:
            ifsim.run(SCENE, set=failing)
        partial = e.exception.result
        self.assertEqual(partial.summary["status"], "failed")
        self.assertGreater(len(partial["t_t1"]), 10)
        self.assertLess(len(partial["t_t1"]), 1001)
        self.assertIn("did not converge", str(e.exception))
        self.assertFalse(ifsim.run(SCENE, set=failing, check=False).ok)


if __name__ == "__main__":
    unittest.main()
