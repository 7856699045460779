"""Bad input raises sculpt.Error with the engine's message (the one the command line prints for the same
script), and leaves the session as it was."""
import math

import numpy as np
import pytest

import sculpt
from conftest import icosphere, run_cli, write_obj


@pytest.fixture
def sphere(tmp_path):
    V, F = icosphere(2)
    path = tmp_path / "sphere.obj"
    write_obj(path, V, F)
    return V, F, path


def cli_message(tmp_path, cli, mesh_path, ops):
    """What the command line says about a script of these ops, the last one bad (exit code 2, nothing written)."""
    done, out, _ = run_cli(tmp_path, {"ops": ops}, mesh_path)
    assert done.returncode == 2 and not out.exists(), done.stderr
    return done.stderr.splitlines()[0]


# (module call, the same op as a script line, the part of the message both must carry)
CASES = [
    (lambda s: s.drag_vertex(100000, [0, 0, 0]), {"op": "drag_vertex", "vertex": 100000, "target": [0, 0, 0]},
     "100000"),
    (lambda s: s.drag([[9, 9, 9]], [[0, 0, 0]]), {"op": "drag", "constraints": [{"source": [9, 9, 9], "target": [0, 0, 0]}]},
     "is not inside the deformed lattice"),
    (lambda s: s.move_control_points([[0, 0, 99]], by=[0, 0.1, 0]),
     {"op": "move_control_point", "indices": [[0, 0, 99]], "by": [0, 0.1, 0]}, "is outside the 8x8x8 lattice"),
    (lambda s: s.move_control_points([[1, 1, 1]], to=[0, 0, 0], by=[0, 0, 0]),
     {"op": "move_control_point", "indices": [[1, 1, 1]], "to": [0, 0, 0], "by": [0, 0, 0]},
     "needs exactly one of \"to\" and \"by\""),
    (lambda s: s.drag_vertex(3, [0, 1]), {"op": "drag_vertex", "vertex": 3, "target": [0, 1]},
     "expected an array of 3 numbers"),
    (lambda s: s.drag_vertex(3, [0, 1, 0], strength=2.0), {"op": "drag_vertex", "vertex": 3, "target": [0, 1, 0],
                                                          "strength": 2.0}, "expected a number in (0, 1]"),
    (lambda s: s.setup_lattice(resolution=[2, 2, 2]), {"op": "setup_lattice", "lattice": {"resolution": [2, 2, 2]}},
     "resolution"),
    (lambda s: s.run({"op": "fold"}), {"op": "fold"}, "unknown op \"fold\""),
]


@pytest.mark.parametrize("call,op,needle", CASES)
def test_errors_carry_the_engine_message_and_change_nothing(cli, tmp_path, sphere, call, op, needle):
    V, F, path = sphere
    session = sculpt.load(str(path))
    first = {"op": "drag_vertex", "vertex": 0, "target": (V[0] * 1.1).tolist()}
    session.run(first)
    before, history = session.positions.copy(), session.history
    with pytest.raises(sculpt.Error) as error:
        call(session)
    assert isinstance(error.value, ValueError)
    message = str(error.value)
    assert needle in message
    # The command line's message for the same op ends in the engine's words; the module's carries them too
    # (the command line prefixes "op 0 (kind): " or "ops[0].", the module the command's name).
    engine_words = cli_message(tmp_path, cli, path, [first, op]).split(": ")[-1]
    assert engine_words in message
    assert np.array_equal(session.positions, before)
    assert session.history == history


def test_non_finite_numbers_are_refused_before_the_engine(sphere):
    V, F, path = sphere
    session = sculpt.load(str(path))
    with pytest.raises(sculpt.Error, match=r"target\[1\]: expected a finite number"):
        session.drag_vertex(0, [0.0, math.nan, 0.0])
    with pytest.raises(sculpt.Error, match=r"targets\[0\]\[2\]: expected a finite number"):
        session.drag([V[0]], [[0.0, 0.0, math.inf]])
    with pytest.raises(sculpt.Error, match=r"V\[5\]\[0\] is not finite"):
        bad = V.copy()
        bad[5, 0] = math.nan
        sculpt.Session(bad, F)
    assert np.isfinite(session.positions).all()
    assert session.history["entries"] == 0


def test_arrays_of_the_wrong_shape_or_type(sphere):
    V, F, _ = sphere
    with pytest.raises(sculpt.Error, match=r"V must be n x 3 \(got shape \(\d+, 2\)\)"):
        sculpt.Session(V[:, :2], F)
    with pytest.raises(sculpt.Error, match=r"F must be m x 3"):
        sculpt.Session(V, F.ravel())
    with pytest.raises(sculpt.Error, match=r"F must hold integers"):
        sculpt.Session(V, F.astype(float))
    with pytest.raises(sculpt.Error, match=r"F\[0\]\[1\] = 9999 is out of range \(V has \d+ vertices\)"):
        bad = F.copy()
        bad[0, 1] = 9999
        sculpt.Session(V, bad)
    # A ragged list is named as the argument it is, not as numpy's ValueError.
    ragged = [list(row) for row in V[:4]]
    ragged[2] = ragged[2][:2]
    with pytest.raises(sculpt.Error, match=r"Session: V must be an n x 3 array of numbers, one row each"):
        sculpt.Session(ragged, F)
    ragged_faces = [list(row) for row in F[:4]]
    ragged_faces[1] = ragged_faces[1] + [0]
    with pytest.raises(sculpt.Error, match=r"Session: F must be an m x 3 array of integer numbers, one row each"):
        sculpt.Session(V, ragged_faces)
    # An index beyond the range of int (or of int64) is named as it is.
    for value, dtype in [(np.iinfo(np.uint64).max, np.uint64), (2**40, np.int64), (2**32 + 1, np.uint64)]:
        bad = F.astype(dtype)
        bad[1, 2] = value
        with pytest.raises(sculpt.Error, match=r"F\[1\]\[2\] = %d is out of range" % value):
            sculpt.Session(V, bad)
    with pytest.raises(sculpt.Error, match=r"the mesh has no vertices"):
        sculpt.Session(np.zeros((0, 3)), np.zeros((0, 3), dtype=int))
    with pytest.raises(sculpt.Error, match=r"drag: sources and targets"):
        sculpt.Session(V, F).drag([V[0], V[1]], [V[0]])


def test_files_and_settings(tmp_path, sphere):
    with pytest.raises(sculpt.Error, match=r"load: cannot read .*missing\.obj"):
        sculpt.load(str(tmp_path / "missing.obj"))
    broken = tmp_path / "broken.obj"
    broken.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n")
    with pytest.raises(sculpt.Error, match=r"broken\.obj:4: "):
        sculpt.load(str(broken))
    with pytest.raises(sculpt.Error, match=r"lattice\.resolutoin: unknown field"):
        sculpt.load(str(sphere[2]), lattice={"resolutoin": [4, 4, 4]})
    with pytest.raises(sculpt.Error, match=r"injectivity\.mode: expected \"off\", \"conic\" or \"exact\""):
        sculpt.load(str(sphere[2]), injectivity={"mode": "strict"})
    session = sculpt.load(str(sphere[2]))
    with pytest.raises(sculpt.Error, match=r"save: "):
        session.save(str(tmp_path / "no" / "such" / "folder" / "out.obj"))
