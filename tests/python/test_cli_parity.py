"""The module runs the command line's commands: random scripts over several mesh sizes (fixed seeds) give the
same positions, bit for bit, and the same reports (all but the times) as `sculpt --headless` on that script."""
import numpy as np
import pytest

import sculpt
from conftest import random_mesh, read_obj_positions, run_cli, without_timings, write_obj


def random_op(rng, session, size):
    """A random drag, vertex drag, control-point move, lattice set-up, undo or redo for the session as it is now
    (sources are points of its current shape; some moves large enough to be subdivided or refused)."""
    V = session.positions
    resolution = session.lattice["resolution"]
    reach = size * (0.4 if rng.random() < 0.2 else 0.06)
    kind = rng.choice(["drag", "drag_vertex", "drag_vertex", "move", "setup", "undo", "redo"])
    if kind == "drag":
        sources = V[rng.integers(0, len(V), int(rng.integers(1, 3)))]
        targets = sources + rng.standard_normal(sources.shape) * reach
        return {"op": "drag", "constraints": [{"source": s.tolist(), "target": t.tolist()}
                                              for s, t in zip(sources, targets)]}
    if kind == "drag_vertex":
        v = int(rng.integers(0, len(V)))
        op = {"op": "drag_vertex", "vertex": v, "target": (V[v] + rng.standard_normal(3) * reach).tolist()}
        if rng.random() < 0.3:
            op["radius"] = 0.3 * size
        return op
    if kind == "move":
        indices = [[int(rng.integers(0, r)) for r in resolution] for _ in range(int(rng.integers(1, 4)))]
        return {"op": "move_control_point", "indices": indices, "by": (rng.standard_normal(3) * reach).tolist()}
    if kind == "setup":
        degree = int(rng.integers(1, 4))
        return {"op": "setup_lattice", "lattice": {"resolution": [int(r) for r in rng.integers(4, 8, 3)],
                                                   "degree": [degree] * 3, "padding": float(rng.uniform(0.02, 0.1))}}
    return {"op": str(kind)}


def apply_op(session, op):
    """One script op through the module's own method for it."""
    brush = {k: op[k] for k in ("radius", "strength", "falloff", "symmetry") if k in op}
    if op["op"] == "drag":
        return session.drag([c["source"] for c in op["constraints"]], [c["target"] for c in op["constraints"]],
                            **brush)
    if op["op"] == "drag_vertex":
        return session.drag_vertex(op["vertex"], op["target"], **brush)
    if op["op"] == "move_control_point":
        return session.move_control_points(op["indices"], by=op["by"])
    if op["op"] == "setup_lattice":
        return session.setup_lattice(**op["lattice"])
    return getattr(session, op["op"])()


@pytest.mark.parametrize("level,seed", [(1, 11), (1, 12), (2, 21), (2, 22), (3, 31)])
def test_random_scripts_match_the_command_line(cli, tmp_path, level, seed):
    rng = np.random.default_rng(seed)
    V, F = random_mesh(rng, level)
    mesh_path = tmp_path / "mesh.obj"
    write_obj(mesh_path, V, F)
    size = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))
    degree = int(rng.integers(1, 4))
    script = {"lattice": {"resolution": [int(r) for r in rng.integers(4, 8, 3)], "degree": [degree] * 3},
              "injectivity": {"mode": "conic", "max_depth": 4}, "ops": []}

    # The ops are chosen as the module runs them; one that is bad input (a source the deformation carried
    # out of the lattice) raises, changes nothing, and is left out of the script.
    by_method = sculpt.load(str(mesh_path), lattice=script["lattice"], injectivity=script["injectivity"])
    reports = []
    while len(script["ops"]) < 10:
        op = random_op(rng, by_method, size)
        before, history = by_method.positions.copy(), by_method.history
        try:
            reports.append(apply_op(by_method, op))
        except sculpt.Error:
            assert np.array_equal(by_method.positions, before) and by_method.history == history
            continue
        script["ops"].append(op)

    done, cli_obj, cli_report = run_cli(tmp_path, script, mesh_path)
    assert done.returncode == 0, done.stderr
    statuses = [r["status"] for r in cli_report["ops"]]
    assert [without_timings(r) for r in reports] == [without_timings(r) for r in cli_report["ops"]], statuses
    cli_positions = read_obj_positions(cli_obj)
    assert np.array_equal(by_method.positions, cli_positions)
    assert by_method.lattice == cli_report["lattice"]
    assert by_method.history["entries"] == cli_report["history"]["entries"]
    assert by_method.history["cursor"] == cli_report["history"]["cursor"]

    # The same script through run(), on the mesh given as arrays.
    by_run = sculpt.Session(V, F, lattice=script["lattice"], injectivity=script["injectivity"])
    assert [without_timings(by_run.run(op)) for op in script["ops"]] == [without_timings(r) for r in reports]
    assert np.array_equal(by_run.positions, cli_positions)

    # save() writes what the command line's --output writes.
    saved = tmp_path / "module_out.obj"
    by_method.save(str(saved))
    assert saved.read_bytes() == cli_obj.read_bytes()


def test_the_demo_script_matches_the_command_line(cli, tmp_path):
    """The bundled demo (10k vertices, a subdivided drag) as the README's quick start runs it."""
    import json
    from conftest import SOURCE_DIR
    script = json.loads((SOURCE_DIR / "assets" / "demo.json").read_text())
    mesh = SOURCE_DIR / "assets" / "default.obj"
    done, cli_obj, cli_report = run_cli(tmp_path, script, mesh)
    assert done.returncode == 0, done.stderr
    session = sculpt.load(str(mesh), lattice=script["lattice"], injectivity=script["injectivity"])
    reports = [session.run(op) for op in script["ops"]]
    assert [without_timings(r) for r in reports] == [without_timings(r) for r in cli_report["ops"]]
    assert np.array_equal(session.positions, read_obj_positions(cli_obj))
