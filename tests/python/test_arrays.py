"""Session.positions and Session.triangles are views of the engine's rows without a copy, and stay safe: read-only,
following the session in place, keeping it alive, and never left pointing at rows the engine moved."""
import gc

import numpy as np
import pytest

import sculpt
from conftest import icosphere


@pytest.fixture
def session():
    V, F = icosphere(2)
    return sculpt.Session(V, F, lattice={"resolution": [6, 6, 6]})


def address(array):
    return array.__array_interface__["data"][0]


def test_views_share_the_engine_rows(session):
    a, b = session.positions, session.positions
    assert address(a) == address(b) and np.shares_memory(a, b)
    assert a.dtype == np.float64 and a.shape == (162, 3) and a.flags.c_contiguous and not a.flags.owndata
    t = session.triangles
    assert t.dtype == np.int32 and t.shape == (320, 3) and address(t) == address(session.triangles)


def test_views_follow_the_session_in_place(session):
    view = session.positions
    kept = view.copy()
    report = session.drag_vertex(7, (kept[7] * 1.2).tolist())
    assert report["status"] == "applied"
    assert not np.array_equal(view, kept)
    assert np.array_equal(view, session.positions) and address(view) == address(session.positions)
    session.undo()
    # Undo is the inverse manipulation (it subtracts the step's control displacement): back to rounding.
    assert np.allclose(view, kept, rtol=0, atol=1e-12)


def test_views_are_read_only(session):
    view = session.positions
    with pytest.raises(ValueError):
        view[0, 0] = 1.0
    with pytest.raises(ValueError):
        view.setflags(write=True)
    with pytest.raises(ValueError):
        session.triangles[0, 0] = 1


def test_a_view_keeps_its_session_alive():
    V, F = icosphere(1)
    view = sculpt.Session(V, F).positions
    gc.collect()
    assert np.array_equal(view, V)
    derived = view[3:5]  # numpy views of the view keep it (and so the session) alive too
    del view
    gc.collect()
    assert np.array_equal(derived, V[3:5])


def test_commands_that_would_move_the_rows_wait_for_the_views(session):
    session.drag_vertex(5, (session.positions[5] * 1.5).tolist())
    view = session.positions
    row_slice = view[:10]
    with pytest.raises(sculpt.Error, match="may change the number of vertices.*delete them first"):
        session.run({"op": "refine", "tolerance": 0.0005})
    del view
    with pytest.raises(sculpt.Error, match="view"):
        session.run({"op": "refine", "tolerance": 0.0005})  # row_slice still looks at the rows
    del row_slice
    gc.collect()
    report = session.run({"op": "refine", "tolerance": 0.0005})
    assert report["status"] == "applied" and report["vertices_added"] > 0
    assert session.positions.shape == (162 + report["vertices_added"], 3)
    assert session.triangles.shape[0] == 320 + report["triangles_added"]
    # Undoing the refinement removes vertices: refused while a view is alive, done once it is not.
    view = session.positions
    with pytest.raises(sculpt.Error, match="undo may change the number of vertices"):
        session.undo()
    del view
    assert session.undo()["status"] == "applied"
    assert session.positions.shape == (162, 3)


def test_automatic_refinement_makes_every_edit_wait_for_the_views(session):
    session.run({"op": "set_refinement", "automatic": True, "tolerance": 0.0005})
    view = session.positions
    with pytest.raises(sculpt.Error, match="drag_vertex may change the number of vertices"):
        session.drag_vertex(5, (view[5] * 1.5).tolist())
    target = (view[5] * 1.5).tolist()
    del view
    assert session.drag_vertex(5, target)["status"] == "applied"


def test_arrays_of_other_types_are_converted(session):
    V, F = icosphere(1)
    a = sculpt.Session(V.astype(np.float32).astype(np.float64), F.astype(np.int32))
    b = sculpt.Session(V.astype(np.float32), F.astype(np.uint16).tolist())
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.triangles, b.triangles)
    # numpy scalars and arrays in arguments
    report = b.drag_vertex(np.int64(3), np.asarray(b.positions[3]) * np.float64(1.1))
    assert report["status"] == "applied"
    assert np.isfinite(b.positions).all()
