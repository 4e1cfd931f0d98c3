"""ifsim from Python: run a scene in-process and get its history as NumPy arrays.

    import ifsim
    r = ifsim.run("scenes/simple-shear-cnl-stutz.toml",
                  set={"interface.roughness": 0.9, "interface.subincrement": "adaptive"})
    r.history["t_t1"]            # NumPy array, one entry per row of history.csv
    r.summary["results"]         # summary.json as a dict
    r = ifsim.run({"kind": "element-test", "material": {...}, ...})   # a scene as a dict

Errors arrive as exceptions: ifsim.SceneError (a ValueError) with the scene error's text (file,
key, what was expected), ifsim.RunFailed (a RuntimeError) when the simulation fails, with the
partial result as .result; KeyboardInterrupt when Ctrl-C stopped the run. See docs/python.md.
"""

import csv
import json
import os
import shutil
import tempfile
import threading

import numpy as np

from . import _ifsim

__all__ = ["run", "Result", "SceneError", "RunFailed", "version", "revision"]
version = _ifsim.version
revision = _ifsim.revision

_EXIT_OK, _EXIT_IO, _EXIT_BAD_INPUT, _EXIT_RUN_FAILED = 0, 1, 2, 3
_EXIT_SIGINT = 128 + 2
# One run at a time in this process: a run installs process-wide signal handlers and sets the
# process-wide thread count (threads in Python wait here; use `ifsim sweep` for many at once).
_ONE_RUN = threading.Lock()


class SceneError(ValueError):
    """The scene (or an override) is not valid: the text names the file, key and expectation."""


class RunFailed(RuntimeError):
    """The simulation failed; .result holds the rows up to the failure and the summary."""

    def __init__(self, reason, result):
        super().__init__(reason)
        self.result = result


class Result:
    """A finished run: history (column name -> NumPy array), summary (dict), out (folder or
    None when the run went to a temporary folder that is gone)."""

    def __init__(self, history, summary, out):
        self.history = history
        self.summary = summary
        self.out = out

    @property
    def ok(self):
        return self.summary.get("status") == "ok"

    def __getitem__(self, column):
        return self.history[column]

    def __repr__(self):
        rows = len(next(iter(self.history.values()))) if self.history else 0
        return (f"<ifsim.Result {self.summary.get('kind')} {self.summary.get('status')}: "
                f"{rows} rows, {len(self.history)} columns>")


def _read_history(path):
    if not os.path.exists(path):
        return {}
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        rows = [r for r in reader if len(r) == len(header)]
    return {name: np.array([float(r[i]) if r[i] != "" else np.nan for r in rows])
            for i, name in enumerate(header)}


def _read_summary(path):
    if not os.path.exists(path):
        return {}
    with open(path) as f:
        return json.load(f)


def _overrides(set):
    if set is None:
        return []
    if isinstance(set, dict):
        return [f"{k}={_ifsim.value_text(v)}" for k, v in set.items()]
    return list(set)  # "KEY=VALUE" strings, as on the command line


def _absolute_mesh_file(scene):
    # A dict scene runs from a temporary file: a relative mesh file is meant from here.
    mesh = scene.get("mesh")
    if isinstance(mesh, dict) and isinstance(mesh.get("file"), str):
        if not os.path.isabs(mesh["file"]):
            scene = dict(scene, mesh=dict(mesh, file=os.path.abspath(mesh["file"])))
    return scene


def run(scene, out=None, set=None, threads=None, scalar=False, check=True, progress=False):
    """Runs a scene (a file path, or a dict with the file's tables) and returns a Result.

    out:      folder for the run's files (history.csv, summary.json, ...); None = a temporary
              folder, removed after reading.
    set:      overrides, a dict {"interface.roughness": 0.9} or a list of "KEY=VALUE" strings.
    threads:  worker threads (None = all cores); scalar: the scalar kernel path.
    check:    raise RunFailed when the run fails (False: return the failed Result).
    progress: show the progress line on stderr.
    """
    scratch = tempfile.mkdtemp(prefix="ifsim-")
    try:
        if isinstance(scene, dict):
            path = os.path.join(scratch, "scene-from-dict.toml")
            with open(path, "w") as f:
                f.write(_ifsim.scene_text(_absolute_mesh_file(scene)))
        else:
            path = os.fspath(scene)
        folder = os.fspath(out) if out is not None else os.path.join(scratch, "run")
        # An earlier run's summary in `out` must not be read as this run's (a run that stops on
        # its command line writes none; --replace removes the earlier outputs otherwise).
        stale = os.path.join(folder, "summary.json")
        if os.path.exists(stale):
            os.remove(stale)
        args = ["run", path, "--out", folder, "--replace"]
        for s in _overrides(set):
            args += ["--set", s]
        if threads is not None:
            args += ["--threads", str(int(threads))]
        if scalar:
            args.append("--scalar")
        args.append("--progress" if progress else "--quiet")
        with _ONE_RUN:
            code = _ifsim.run_cli(args)
        summary = _read_summary(os.path.join(folder, "summary.json"))
        result = Result(_read_history(os.path.join(folder, "history.csv")), summary,
                        folder if out is not None else None)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    reason = summary.get("reason", "")
    if code == _EXIT_BAD_INPUT:
        raise SceneError(reason.removeprefix("scene error: ") or
                         f"ifsim could not run {path} (bad command line or scene)")
    if code == _EXIT_IO:
        raise OSError(reason or f"ifsim could not run {path} or write its results to {folder}")
    if code == _EXIT_SIGINT:
        raise KeyboardInterrupt(reason)
    if code > 128:
        raise RunFailed(reason or f"ifsim run stopped by signal {code - 128}", result)
    if code == _EXIT_RUN_FAILED and check:
        raise RunFailed(reason, result)
    return result
