// The Python module `sculpt` (pybind11): a session over the engine, driven by the script commands.
//
// Every command goes through the same path as a line of an OPS.json script: the Python arguments become that
// op's JSON object (field names as in docs/scripting.md "Script format"), io::parseScript reads and checks it, and
// io::runScriptOp runs it, the function the window's commands and the command line go through. So a
// Python call accepts what a script accepts, refuses what it refuses with the same message, and returns the
// same report fields as the command line's REPORT.json (io::reportToJson). Mesh files go through the OBJ
// reader and writer the command line uses, screenshots through its offscreen renderer (app::ScreenshotRenderer).
//
// Errors: anything a caller or a file can cause raises sculpt.Error (a ValueError) with the engine's message,
// prefixed by the command, and leaves the session as it was (the engine's commands change nothing on error).
// Exceptions stay in this file: the engine below returns Status values (house style 7).
//
// Zero-copy arrays: Session.positions and Session.triangles are read-only numpy views of the engine's own
// rows (Positions and Triangles are row-major #V x 3 / #T x 3, numpy's C order). How they stay safe:
//  - each view holds a reference to its session, so the memory outlives neither;
//  - the engine reallocates those rows only when the number of vertices changes (a refinement, or its undo
//    and redo); the session counts its live views and refuses such a command while one is alive, naming the
//    way out (drop the views, or keep copies);
//  - the views are read-only (writing into the engine's rows would bypass the lattice, the history and the
//    triangle check); a command changes them in place, so a view always shows the current shape;
//  - the interpreter lock is held while a command runs, so no Python thread reads rows being written.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <regex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/cli_options.h"
#include "app/screenshot_hook.h"
#include "core/spline/bernstein.h"
#include "core/spline/bernstein_box.h"
#include "io/script.h"
#include "core/session/session.h"
#include "io/mesh_file.h"
#include "io/script_json.h"

namespace py = pybind11;
using nlohmann::json;

namespace sculpt::python {

namespace {

// What sculpt.Error carries: a message for a user, naming what is wrong.
struct SculptError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// ---- mesh files: the command line's reader and writer (io/mesh_file.h), any format by its extension ----

// Reads the mesh file at path (.obj .ply .stl .gltf .glb). Errors name the file and what is wrong; warnings name
// what is kept but not used, or not kept.
Status loadMeshFile(const std::string& path, io::ObjMesh& mesh, std::vector<std::string>& warnings) {
    return io::loadMesh(path, mesh, &warnings);
}

// Writes `mesh` with the session's current positions (#V x 3, the rows after any refinement) to path in the
// format of its extension, atomically: the refined triangles where the engine split edges; an OBJ loaded from
// a file keeps its own text. warnings: what the format cannot hold.
Status saveMeshFile(const std::string& path, const io::ObjMesh& mesh, const core::Session& session,
                    std::vector<std::string>& warnings) {
    return io::saveRefinedMesh(path, mesh, session.refinement().appliedSplits(), session.mesh().positions, &warnings);
}

// ---- Python values to script JSON ----

// A Python value as JSON: None, bool, int, float (finite only), str, dict (str keys), list, tuple, and numpy
// arrays and scalars (through tolist()). `path` names the value in errors ("target[1]").
json toJson(py::handle value, const std::string& path) {
    if (value.is_none()) return nullptr;
    if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
    if (py::isinstance<py::int_>(value)) {
        const long long i = PyLong_AsLongLong(value.ptr());
        if (i == -1 && PyErr_Occurred()) {
            PyErr_Clear();
            throw SculptError(path + ": integer out of range");
        }
        return i;
    }
    if (py::isinstance<py::float_>(value)) {
        const double d = value.cast<double>();
        if (!std::isfinite(d)) throw SculptError(path + ": expected a finite number (got " + std::string(py::str(value)) + ")");
        return d;
    }
    if (py::isinstance<py::str>(value)) return value.cast<std::string>();
    if (py::isinstance<py::dict>(value)) {
        json object = json::object();
        for (auto item : value.cast<py::dict>()) {
            if (!py::isinstance<py::str>(item.first)) throw SculptError(path + ": keys must be strings");
            const std::string key = item.first.cast<std::string>();
            object[key] = toJson(item.second, path.empty() ? key : path + "." + key);
        }
        return object;
    }
    if (py::hasattr(value, "tolist") && !py::isinstance<py::bytes>(value)) return toJson(value.attr("tolist")(), path);
    if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
        json array = json::array();
        size_t i = 0;
        for (py::handle item : value) array.push_back(toJson(item, path + "[" + std::to_string(i++) + "]"));
        return array;
    }
    throw SculptError(path + ": expected numbers, lists or strings (got a " + std::string(py::str(value.get_type().attr("__name__"))) + ")");
}

// One op (its JSON object) parsed as a script line would be. Field paths in errors drop the "ops[0]." a
// script has, and a drag's "constraints[i].source" reads "sources[i]" (the Python argument it came from).
io::ScriptOp parseOp(const json& op, const std::string& command) {
    io::Script script;
    const json root = {{"ops", json::array({op})}};
    if (Status s = io::parseScript(root.dump(), command, script); !s) {
        std::string message = s.message;
        for (const std::string prefix : {"ops[0].", "ops[0]: "}) {
            const size_t at = message.find(prefix);
            if (at != std::string::npos) message.erase(at, prefix.size());
        }
        message = std::regex_replace(message, std::regex(R"(constraints\[(\d+)\]\.(source|target))"), "$2s[$1]");
        throw SculptError(message);
    }
    return script.ops.front();
}

// The lattice and injectivity settings as a script's top level gives them (defaults where absent).
io::Script parseSettings(py::handle lattice, py::handle injectivity, const std::string& command) {
    json root = json::object();
    if (!lattice.is_none()) root["lattice"] = toJson(lattice, "lattice");
    if (!injectivity.is_none()) root["injectivity"] = toJson(injectivity, "injectivity");
    io::Script script;
    if (Status s = io::parseScript(root.dump(), command, script); !s) throw SculptError(s.message);
    return script;
}

// The brush fields of drag and drag_vertex: only those given.
void addBrush(json& op, py::handle radius, py::handle strength, py::handle falloff, py::handle symmetry) {
    if (!radius.is_none()) op["radius"] = toJson(radius, "radius");
    if (!strength.is_none()) op["strength"] = toJson(strength, "strength");
    if (!falloff.is_none()) op["falloff"] = toJson(falloff, "falloff");
    if (!symmetry.is_none()) op["symmetry"] = toJson(symmetry, "symmetry");
}

// A list of points: one [x,y,z] becomes [[x,y,z]].
json pointList(py::handle value, const std::string& path) {
    json points = toJson(value, path);
    if (points.is_array() && points.size() == 3 && points[0].is_number()) points = json::array({points});
    return points;
}

// ---- the session ----

class PySession {
public:
    core::Session session;
    io::ObjMesh mesh;                   // what save() writes: a loaded file keeps its text
    std::string source;                 // the file it was loaded from, or "" (arrays)
    std::vector<std::string> warnings;  // the loader's
    int liveViews = 0;                  // numpy views of the engine's rows alive now

    // Sets the mesh and the settings as the command line does before a script's first op.
    void start(const io::Script& settings, bool trackJacobian, const std::string& what) {
        session.setTrackJacobian(trackJacobian);
        if (Status s = session.setMesh(mesh.positions, mesh.triangles, settings.lattice); !s)
            throw SculptError(what + ": " + s.message);
        session.setInjectivity(settings.injectivity);
    }

    // Runs one op and returns its report (the command line's per-op report fields).
    py::dict run(const io::ScriptOp& op, const std::string& command) {
        if (op.kind == io::ScriptOp::Kind::BeginGroup || op.kind == io::ScriptOp::Kind::EndGroup)
            throw SculptError(command + ": begin_group and end_group pair up within one script; use the \"group\" op");
        if (liveViews > 0 && mayChangeVertexCount(op))
            throw SculptError(command + ": " + io::scriptOpName(op.kind) +
                              " may change the number of vertices (a refinement, or its undo or redo), which moves the "
                              "engine's rows, while " + std::to_string(liveViews) +
                              " view(s) of them from Session.positions or Session.triangles are alive: delete them first "
                              "(keep .copy() of them instead)");
        const double* rowsBefore = session.mesh().positions.data();
        const Eigen::Index countBefore = session.mesh().positions.rows();
        core::OpReport report;
        Status s = op.kind == io::ScriptOp::Kind::Screenshot ? screenshot(op.path, app::CliOptions{})
                                                               : io::runScriptOp(session, op, report);
        if (!s) throw SculptError(command + ": " + s.message);
        if (op.kind == io::ScriptOp::Kind::Screenshot) {
            report.status = core::OpStatus::Applied;
            report.reason = "wrote " + op.path;
        }
        // The guard above is what keeps views valid; this catches an engine path it does not know about.
        if (liveViews > 0 && (session.mesh().positions.data() != rowsBefore || session.mesh().positions.rows() != countBefore))
            throw std::logic_error(std::string(io::scriptOpName(op.kind)) + " moved the engine's rows while views were alive");
        report.op = io::scriptOpName(op.kind);
        io::ScriptReport one;
        one.ops.push_back(std::move(report));
        py::dict reportDict = reportRoot(one)["ops"].cast<py::list>()[0].cast<py::dict>();
        reportDict.attr("pop")("index");
        return reportDict;
    }

    // The command line's REPORT.json (io::reportToJson) for these ops, as Python objects.
    py::dict reportRoot(const io::ScriptReport& report) const {
        io::ReportContext context;
        context.input = source;
        context.vertexCount = static_cast<int>(session.mesh().positions.rows());
        context.triangleCount = static_cast<int>(session.mesh().triangles.rows());
        const std::string text = io::reportToJson(report, session, context);
        return py::module_::import("json").attr("loads")(text).cast<py::dict>();
    }

    // One top-level field of that report (lattice, history, injectivity) for the session as it is now.
    py::object reportField(const char* name) const {
        const py::dict root = reportRoot({});
        return root[name];
    }

    Status screenshot(const std::string& path, const app::CliOptions& options) const {
        app::ScreenshotRenderer renderer(options);
        return renderer.capture(session, path);
    }

private:
    // Could `op` change the number of vertices (and so reallocate the rows views point into)?
    bool mayChangeVertexCount(const io::ScriptOp& op) const {
        const auto& history = session.history();
        const int cursor = session.history().cursor();
        switch (op.kind) {
            case io::ScriptOp::Kind::Refine: return true;
            case io::ScriptOp::Kind::Undo:
                return cursor > 0 && !(history[static_cast<size_t>(cursor - 1)].refinement.empty() && history[static_cast<size_t>(cursor - 1)].refinementBefore.empty());
            case io::ScriptOp::Kind::Redo:
                return cursor < static_cast<int>(history.size()) &&
                       !(history[static_cast<size_t>(cursor)].refinement.empty() && history[static_cast<size_t>(cursor)].refinementBefore.empty());
            case io::ScriptOp::Kind::Screenshot:
            case io::ScriptOp::Kind::SetRefinement:
            case io::ScriptOp::Kind::SetPins: return false;
            // a brush stroke may be split under its pull
            case io::ScriptOp::Kind::Drag:
            case io::ScriptOp::Kind::DragVertex:
                return session.refinement().settings().automatic || (op.brush.active() && session.refinement().settings().underBrush);
            default: return session.refinement().settings().automatic;  // any edit may be refined after it
        }
    }
};

// A read-only numpy view of rows owned by the session behind `owner` (see the file comment).
// What a view's base (a capsule) holds: a reference to the session, and its count of live views.
struct ViewToken {
    py::object owner;
    PySession* session;
};

void releaseViewToken(void* pointer) {
    auto* token = static_cast<ViewToken*>(pointer);
    --token->session->liveViews;
    delete token;  // drops the reference to the session (the capsule's destructor runs with the GIL held)
}

template <typename Matrix>
py::array engineView(py::object owner, const Matrix& rows) {
    using Scalar = typename Matrix::Scalar;
    PySession& session = owner.cast<PySession&>();
    auto* token = new ViewToken{owner, &session};
    ++session.liveViews;
    py::capsule base(static_cast<const void*>(token), &releaseViewToken);
    py::array view(py::dtype::of<Scalar>(), {static_cast<py::ssize_t>(rows.rows()), static_cast<py::ssize_t>(3)},
                   {static_cast<py::ssize_t>(3 * sizeof(Scalar)), static_cast<py::ssize_t>(sizeof(Scalar))}, rows.data(), base);
    view.attr("setflags")(py::arg("write") = false);
    return view;
}

// V (n x 3, float64 or anything numpy casts to it) and F (m x 3, integers) as an ObjMesh built in code.
io::ObjMesh meshFromArrays(py::handle vertices, py::handle faces) {
    py::module_ np = py::module_::import("numpy");
    // A ragged list (rows of different lengths) is numpy's ValueError: named here as the argument it is.
    const auto asArray = [&np](py::handle value, const char* what, const char* shape) {
        try {
            return py::array(np.attr("asarray")(value));
        } catch (py::error_already_set& e) {
            if (!e.matches(PyExc_ValueError) && !e.matches(PyExc_TypeError)) throw;
            throw SculptError(std::string("Session: ") + what + " must be " + shape + " numbers, one row each (" +
                              e.value().attr("__str__")().cast<std::string>() + ")");
        }
    };
    py::array V = asArray(vertices, "V", "an n x 3 array of");
    py::array F = asArray(faces, "F", "an m x 3 array of integer");
    auto shapeText = [](const py::array& a) { return std::string(py::str(py::tuple(a.attr("shape")))); };
    if (V.ndim() != 2 || V.shape(1) != 3) throw SculptError("Session: V must be n x 3 (got shape " + shapeText(V) + ")");
    if (F.ndim() != 2 || F.shape(1) != 3) throw SculptError("Session: F must be m x 3 (got shape " + shapeText(F) + ")");
    const char kind = V.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u')
        throw SculptError("Session: V must hold numbers (got dtype " + std::string(py::str(V.dtype())) + ")");
    const char faceKind = F.dtype().kind();
    if (faceKind != 'i' && faceKind != 'u' && !(F.shape(0) == 0))
        throw SculptError("Session: F must hold integers (got dtype " + std::string(py::str(F.dtype())) + ")");
    auto positions = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(V);
    // Unsigned 64-bit indices are read as such: a uint64 max is named as it is, not as the -1 it casts to.
    const bool unsignedFaces = faceKind == 'u';
    auto indices = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(unsignedFaces ? py::array() : F);
    auto unsignedIndices = py::array_t<unsigned long long, py::array::c_style | py::array::forcecast>::ensure(unsignedFaces ? F : py::array());
    if (!positions || (unsignedFaces ? !unsignedIndices : !indices)) throw py::error_already_set();

    io::ObjMesh mesh;
    const py::ssize_t n = V.shape(0), m = F.shape(0);
    mesh.positions.resize(n, 3);
    const double* p = positions.data();
    for (py::ssize_t i = 0; i < n * 3; ++i) {
        if (!std::isfinite(p[i]))
            throw SculptError("Session: V[" + std::to_string(i / 3) + "][" + std::to_string(i % 3) + "] is not finite");
        mesh.positions.data()[i] = p[i];
    }
    mesh.triangles.resize(m, 3);
    for (py::ssize_t i = 0; i < m * 3; ++i) {
        const bool inRange = unsignedFaces ? unsignedIndices.data()[i] < static_cast<unsigned long long>(n)
                                           : indices.data()[i] >= 0 && indices.data()[i] < n;
        if (!inRange)
            throw SculptError("Session: F[" + std::to_string(i / 3) + "][" + std::to_string(i % 3) + "] = " +
                              (unsignedFaces ? std::to_string(unsignedIndices.data()[i]) : std::to_string(indices.data()[i])) +
                              " is out of range (V has " + std::to_string(n) + " vertices)");
        mesh.triangles.data()[i] = static_cast<int>(unsignedFaces ? static_cast<long long>(unsignedIndices.data()[i]) : indices.data()[i]);
    }
    // One polygon per triangle, in the default group, without texture coordinates or normals (obj_mesh.h's
    // invariants); saving writes it from these arrays.
    mesh.groupNames = {""};
    mesh.faceStart.push_back(0);
    for (py::ssize_t t = 0; t < m; ++t) {
        for (int c = 0; c < 3; ++c) {
            mesh.cornerVertex.push_back(mesh.triangles(t, c));
            mesh.cornerTexcoord.push_back(-1);
            mesh.cornerNormal.push_back(-1);
        }
        mesh.faceStart.push_back(static_cast<int>(3 * (t + 1)));
        mesh.triangleFace.push_back(static_cast<int>(t));
        mesh.faceGroup.push_back(0);
        mesh.faceMaterial.push_back(-1);
    }
    mesh.texcoords.resize(0, 2);
    if (Status s = io::checkObjMesh(mesh); !s) throw SculptError("Session: " + s.message);
    return mesh;
}

// Screenshot options as the command line's --size, --camera, --overlay and --gl-backend take them.
app::CliOptions screenshotOptions(py::handle size, py::handle camera, py::handle overlays, const std::string& glBackend) {
    app::CliOptions options;
    const json sizeJson = toJson(size, "size");
    auto isSide = [](const json& v) { return v.is_number_integer() && v.get<long long>() >= 1 && v.get<long long>() <= 16384; };
    if (!sizeJson.is_array() || sizeJson.size() != 2 || !isSide(sizeJson[0]) || !isSide(sizeJson[1]))
        throw SculptError("screenshot: size: expected (width, height), integers in [1, 16384] (got " + sizeJson.dump() + ")");
    options.width = sizeJson[0].get<int>();
    options.height = sizeJson[1].get<int>();
    if (!camera.is_none()) {
        const json c = toJson(camera, "camera");
        if (!c.is_array() || c.size() != 3 || !c[0].is_number() || !c[1].is_number() || !c[2].is_number() || c[2].get<double>() <= 0.0)
            throw SculptError("screenshot: camera: expected (yaw, pitch, distance): degrees, degrees, > 0 in the mesh's units (got " +
                              c.dump() + ")");
        options.camera = std::array<double, 3>{c[0].get<double>(), c[1].get<double>(), c[2].get<double>()};
    }
    const json names = toJson(overlays, "overlays");
    if (!names.is_array()) throw SculptError("screenshot: overlays: expected a list of names");
    for (const json& name : names) {
        if (!name.is_string() || (name != "jacobian" && name != "affected" && name != "lattice" && name != "wireframe"))
            throw SculptError("screenshot: overlays: each must be \"jacobian\", \"affected\", \"lattice\" or \"wireframe\" (got " +
                              name.dump() + ")");
        options.overlays.push_back(name.get<std::string>());
    }
    if (glBackend != "auto" && glBackend != "osmesa" && glBackend != "egl")
        throw SculptError("screenshot: gl_backend: expected \"auto\", \"osmesa\" or \"egl\" (got \"" + glBackend + "\")");
    options.glBackend = glBackend;
    return options;
}

}  // namespace

}  // namespace sculpt::python

using sculpt::python::PySession;
using sculpt::python::SculptError;
namespace sp = sculpt::python;

namespace sculpt::python {
namespace {

using namespace pybind11::literals;

// ---- FFD: PyGeM's pygem.FFD with its parameters, on the engine's Bernstein box (core/spline/bernstein_box.h) ----

// The parameters as PyGeM keeps them: numpy arrays the caller may change in place (ffd.array_mu_x[2, 0, 0] = 0.8).
struct PyFfd {
    py::array_t<long long> nControlPoints;
    py::array boxOrigin, boxLength, rotAngle, muX, muY, muZ;
};

py::array floatArray(py::handle value) {
    return py::module_::import("numpy").attr("asarray")(value, "dtype"_a = "float64");
}

// n_control_points set: the displacements become zeros of that shape, as in PyGeM.
void setControlPoints(PyFfd& ffd, py::handle value) {
    py::array_t<long long> n = py::module_::import("numpy").attr("array")(value, "dtype"_a = "int64");
    if (n.ndim() != 1 || n.shape(0) != 3) throw SculptError("FFD: n_control_points must be 3 integers");
    for (int a = 0; a < 3; ++a)
        if (n.at(a) < 1 || n.at(a) > core::kMaxBernsteinDegree + 1)
            throw SculptError("FFD: n_control_points[" + std::to_string(a) + "] is " + std::to_string(n.at(a)) + ": it must be 1 to " +
                              std::to_string(core::kMaxBernsteinDegree + 1));
    ffd.nControlPoints = n;
    const py::tuple shape = py::make_tuple(n.at(0), n.at(1), n.at(2));
    py::module_ np = py::module_::import("numpy");
    ffd.muX = np.attr("zeros")(shape);
    ffd.muY = np.attr("zeros")(shape);
    ffd.muZ = np.attr("zeros")(shape);
}

// The vector parameter `what` as 3 floats.
Eigen::Vector3d threeFloats(const py::array& value, const char* what) {
    py::array_t<double, py::array::c_style | py::array::forcecast> a = floatArray(value);
    if (a.size() != 3) throw SculptError(std::string("FFD: ") + what + " must be 3 numbers");
    return Eigen::Vector3d(a.data()[0], a.data()[1], a.data()[2]);
}

}  // namespace
}  // namespace sculpt::python

using sculpt::python::PyFfd;

PYBIND11_MODULE(sculpt, m) {
    m.doc() = R"doc(DMFFD Sculpt: direct-manipulation free-form deformation of triangle meshes.

A Session holds one mesh in a NURBS control lattice and its undoable history. Its commands are the ops of
the command line's OPS.json scripts (docs/scripting.md "Script format"): same fields, same checks, same messages, and
each returns that op's report as the command line's REPORT.json writes it (a dict: status "applied" /
"rejected" / "no-op", reason, residuals, max_residual, rank_deficient, injectivity, refused_by, sub_steps,
depth_reached, fraction_applied, control_points_changed, vertices_moved, times in ms).

An operation the injectivity test refuses is not an error: its report says "rejected" and why. Bad input
(a wrong shape, a vertex or control point out of range, a source outside the lattice, a non-finite number,
an unreadable file) raises sculpt.Error (a ValueError) with the engine's message, and changes nothing.
Positions are world units (the mesh's own).

    import sculpt
    s = sculpt.load("assets/default.obj", lattice={"resolution": [8, 8, 8]})
    report = s.drag_vertex(17, [0.3, 0.2, 1.1])
    s.undo()
    s.save("out/deformed.obj")
)doc";

    py::register_exception<SculptError>(m, "Error", PyExc_ValueError);

    py::class_<PyFfd>(m, "FFD", R"doc(Free-form deformation by a Bernstein box, with PyGeM's parameters and PyGeM's results.

    ffd = sculpt.FFD([3, 2, 2])
    ffd.box_origin = np.array([-20.0, -55.0, -45.0]); ffd.box_length = np.array([45.0, 90.0, 90.0])
    ffd.rot_angle = np.array([0.0, 10.0, 15.0])              # degrees about x, y, z: R = Rx Ry Rz
    ffd.array_mu_x[2, 0, 0] = 0.8                             # displacements in box lengths
    new_points = ffd(points)                                  # n x 3; points outside the box do not move

The same model as pygem.FFD (Sederberg & Parry 1986; PyGeM's box frame and rotation): a point inside the
closed box moves by R diag(box_length) sum_ijk b_i(u) b_j(v) b_k(w) mu_ijk. It is a plain FFD: no
injectivity test (a Session does that). Computed natively, in parallel over the points.)doc")
        .def(py::init([](py::handle n) {
                 PyFfd ffd;
                 sculpt::python::setControlPoints(ffd, n.is_none() ? py::object(py::make_tuple(2, 2, 2)) : py::reinterpret_borrow<py::object>(n));
                 ffd.boxOrigin = sculpt::python::floatArray(py::make_tuple(0.0, 0.0, 0.0));
                 ffd.boxLength = sculpt::python::floatArray(py::make_tuple(1.0, 1.0, 1.0));
                 ffd.rotAngle = sculpt::python::floatArray(py::make_tuple(0.0, 0.0, 0.0));
                 return ffd;
             }),
             py::arg("n_control_points") = py::none())
        .def_property("n_control_points", [](const PyFfd& f) { return f.nControlPoints; }, &sculpt::python::setControlPoints,
                      "Control points per axis (3 integers); setting it resets the array_mu_* to zeros of that shape.")
        .def_property("box_origin", [](const PyFfd& f) { return f.boxOrigin; }, [](PyFfd& f, py::handle v) { f.boxOrigin = sculpt::python::floatArray(v); },
                      "The box corner of control point (0, 0, 0), world units.")
        .def_property("box_length", [](const PyFfd& f) { return f.boxLength; }, [](PyFfd& f, py::handle v) { f.boxLength = sculpt::python::floatArray(v); },
                      "The box's edge lengths along its own axes (> 0).")
        .def_property("rot_angle", [](const PyFfd& f) { return f.rotAngle; }, [](PyFfd& f, py::handle v) { f.rotAngle = sculpt::python::floatArray(v); },
                      "Rotation of the box about x, y and z in degrees (R = Rx Ry Rz, about box_origin).")
        .def_property("array_mu_x", [](const PyFfd& f) { return f.muX; }, [](PyFfd& f, py::handle v) { f.muX = sculpt::python::floatArray(v); },
                      "Displacements along the box's x axis, in box lengths: an n_control_points-shaped array.")
        .def_property("array_mu_y", [](const PyFfd& f) { return f.muY; }, [](PyFfd& f, py::handle v) { f.muY = sculpt::python::floatArray(v); },
                      "Displacements along the box's y axis, in box lengths.")
        .def_property("array_mu_z", [](const PyFfd& f) { return f.muZ; }, [](PyFfd& f, py::handle v) { f.muZ = sculpt::python::floatArray(v); },
                      "Displacements along the box's z axis, in box lengths.")
        .def(
            "__call__",
            [](const PyFfd& f, py::handle points) {
                sculpt::core::BernsteinBox box;
                for (int a = 0; a < 3; ++a) box.controlPoints[static_cast<size_t>(a)] = static_cast<int>(f.nControlPoints.at(a));
                box.origin = sculpt::python::threeFloats(f.boxOrigin, "box_origin");
                box.lengths = sculpt::python::threeFloats(f.boxLength, "box_length");
                box.rotationDegrees = sculpt::python::threeFloats(f.rotAngle, "rot_angle");
                const py::array* mus[3] = {&f.muX, &f.muY, &f.muZ};
                static const char* const names[3] = {"array_mu_x", "array_mu_y", "array_mu_z"};
                const int n0 = box.controlPoints[0], n1 = box.controlPoints[1], n2 = box.controlPoints[2];
                for (int a = 0; a < 3; ++a) {
                    py::array_t<double, py::array::c_style | py::array::forcecast> mu = sculpt::python::floatArray(*mus[a]);
                    if (mu.ndim() != 3 || mu.shape(0) != n0 || mu.shape(1) != n1 || mu.shape(2) != n2)
                        throw SculptError(std::string("FFD: ") + names[a] + " must have the shape of n_control_points (" +
                                          std::to_string(n0) + ", " + std::to_string(n1) + ", " + std::to_string(n2) + ")");
                    // PyGeM's [i, j, k] (C order) to the engine's i + n0 (j + n1 k).
                    std::vector<double>& out = box.mu[static_cast<size_t>(a)];
                    out.resize(static_cast<size_t>(n0) * static_cast<size_t>(n1) * static_cast<size_t>(n2));
                    for (int i = 0; i < n0; ++i)
                        for (int j = 0; j < n1; ++j)
                            for (int k = 0; k < n2; ++k) out[static_cast<size_t>(i + n0 * (j + n1 * k))] = mu.at(i, j, k);
                }
                py::array_t<double, py::array::c_style | py::array::forcecast> src = sculpt::python::floatArray(points);
                if (src.ndim() != 2 || src.shape(1) != 3)
                    throw SculptError("FFD: the points must be an n x 3 array (got shape " + std::string(py::str(py::tuple(src.attr("shape")))) + ")");
                sculpt::Positions in(src.shape(0), 3), deformed;
                std::copy(src.data(), src.data() + src.size(), in.data());
                sculpt::Status status;
                {
                    py::gil_scoped_release release;
                    status = sculpt::core::deformByBernsteinBox(box, in, deformed);
                }
                if (!status) throw SculptError("FFD: " + status.message);
                py::array_t<double> result({static_cast<py::ssize_t>(deformed.rows()), static_cast<py::ssize_t>(3)});
                std::copy(deformed.data(), deformed.data() + deformed.size(), result.mutable_data());
                return result;
            },
            py::arg("src_pts"), "The points (n x 3) deformed: a new array; points outside the box are returned unchanged.");

    py::class_<PySession>(m, "Session", R"doc(One mesh, its lattice and its history (core::Session).

Made by sculpt.load(path, ...) from a file, or Session(V, F, ...) from arrays.)doc")
        .def(py::init([](py::handle V, py::handle F, py::handle lattice, py::handle injectivity, bool trackJacobian) {
                 auto session = std::make_unique<PySession>();
                 const sculpt::io::Script settings = sp::parseSettings(lattice, injectivity, "Session");
                 session->mesh = sp::meshFromArrays(V, F);
                 session->start(settings, trackJacobian, "Session");
                 return session;
             }),
             py::arg("V"), py::arg("F"), py::kw_only(), py::arg("lattice") = py::none(), py::arg("injectivity") = py::none(),
             py::arg("track_jacobian") = false,
             R"doc(A session on a mesh given as arrays.

V: n x 3 vertex positions (float64, or anything numpy casts to it), finite, n >= 1. World units.
F: m x 3 triangles, integer indices into V (0-based).
lattice: the script's "lattice" object, e.g. {"resolution": [8, 8, 8], "degree": [3, 3, 3],
    "padding": 0.05, "pin_layers": 0, "region": None}; absent fields take the script's defaults.
injectivity: the script's "injectivity" object, e.g. {"mode": "conic", "max_depth": 6, "triangles": True}.
track_jacobian: keep the det J of every frozen lattice (the "jacobian" screenshot overlay shows the whole
    deformation only when this was on from the start; it costs time on subdivided operations).
Raises sculpt.Error naming the wrong shape, dtype, index or field.)doc")
        .def_property_readonly(
            "positions", [](py::object self) { return sp::engineView(self, self.cast<PySession&>().session.mesh().positions); },
            R"doc(The current vertex positions: a read-only #V x 3 float64 numpy view of the engine's rows, no copy.

It changes in place as commands deform the mesh (take .copy() to keep a shape). While any view of it is alive,
a command that may change the number of vertices (refine, automatic refinement, undo or redo of a refinement)
raises sculpt.Error instead of running, since it would move the rows.)doc")
        .def_property_readonly(
            "triangles", [](py::object self) { return sp::engineView(self, self.cast<PySession&>().session.mesh().triangles); },
            "The triangles: a read-only #T x 3 int32 numpy view of the engine's rows (indices into positions), as positions.")
        .def_property_readonly("source", [](const PySession& s) { return s.source; },
                               "The file the mesh was loaded from ('' for arrays).")
        .def_property_readonly("warnings", [](const PySession& s) { return s.warnings; },
                               "The loader's warnings (list of str): what the file holds that the engine does not use.")
        .def_property_readonly(
            "lattice", [](const PySession& s) { return s.reportField("lattice"); },
            "The cage as the report gives it: {'resolution', 'degree', 'box_min', 'box_max'} (world units).")
        .def_property_readonly(
            "history", [](const PySession& s) { return s.reportField("history"); },
            "{'entries', 'cursor', 'bytes', 'lattice_frames'}: the history size, how many entries are applied, its bytes.")
        .def_property_readonly("injectivity", [](const PySession& s) { return s.reportField("injectivity"); },
                               "The injectivity settings: {'mode', 'max_depth', 'triangles'}.")
        .def(
            "drag",
            [](PySession& s, py::handle sources, py::handle targets, py::handle radius, py::handle strength, py::handle falloff,
               py::handle symmetry) {
                json sourceList = sp::pointList(sources, "sources"), targetList = sp::pointList(targets, "targets");
                if (!sourceList.is_array() || !targetList.is_array() || sourceList.size() != targetList.size())
                    throw SculptError("drag: sources and targets: expected k x 3 each, as many targets as sources");
                json constraints = json::array();
                for (size_t i = 0; i < sourceList.size(); ++i)
                    constraints.push_back({{"source", sourceList[i]}, {"target", targetList[i]}});
                json op = {{"op", "drag"}, {"constraints", constraints}};
                sp::addBrush(op, radius, strength, falloff, symmetry);
                return s.run(sp::parseOp(op, "drag"), "drag");
            },
            py::arg("sources"), py::arg("targets"), py::kw_only(), py::arg("radius") = py::none(),
            py::arg("strength") = py::none(), py::arg("falloff") = py::none(), py::arg("symmetry") = py::none(),
            R"doc(Moves points of the current shape onto targets with the least lattice change (Hu et al. 2001 eq. 12).

sources, targets: k x 3 (or one [x, y, z] each), world units; each source a point of the current
    (deformed) shape inside the lattice. Contradicting constraints give the least-squares compromise
    (the report's residuals, per constraint, world units).
radius (world units, 0: whole cage), strength in (0, 1], falloff ("smooth", "medium", "sharp"),
    symmetry ("x", "yz", ...): the brush, as the script's drag fields.
Returns the report dict. Subdivided into injective steps as needed ("sub_steps"); refused ("rejected")
when no injective split exists. Raises sculpt.Error on bad input (names sources[i] / targets[i]).)doc")
        .def(
            "drag_vertex",
            [](PySession& s, py::handle vertex, py::handle target, py::handle radius, py::handle strength, py::handle falloff,
               py::handle symmetry) {
                json op = {{"op", "drag_vertex"}, {"vertex", sp::toJson(vertex, "vertex")}, {"target", sp::toJson(target, "target")}};
                sp::addBrush(op, radius, strength, falloff, symmetry);
                return s.run(sp::parseOp(op, "drag_vertex"), "drag_vertex");
            },
            py::arg("vertex"), py::arg("target"), py::kw_only(), py::arg("radius") = py::none(), py::arg("strength") = py::none(),
            py::arg("falloff") = py::none(), py::arg("symmetry") = py::none(),
            R"doc(Drags mesh vertex `vertex` (0-based, file order) to `target` ([x, y, z], world units). As drag otherwise.)doc")
        .def(
            "move_control_points",
            [](PySession& s, py::handle indices, py::handle to, py::handle by) {
                json op = {{"op", "move_control_point"}};
                json ids = sp::toJson(indices, "indices");
                if (ids.is_array() && ids.size() == 3 && ids[0].is_number()) ids = json::array({ids});
                op["indices"] = ids;
                if (!to.is_none()) op["to"] = sp::toJson(to, "to");
                if (!by.is_none()) op["by"] = sp::toJson(by, "by");
                return s.run(sp::parseOp(op, "move_control_points"), "move_control_points");
            },
            py::arg("indices"), py::kw_only(), py::arg("to") = py::none(), py::arg("by") = py::none(),
            R"doc(Moves cage control points, as the script's move_control_point.

indices: k x 3 lattice indices [i, j, k] (or one). Exactly one of
to: positions, by: offsets; each k x 3, or one [x, y, z] for every point (world units).
A move that would fold the lattice stops at the last injective position ("fraction_applied").
Raises sculpt.Error for pinned points, indices outside the lattice, non-finite values.)doc")
        .def(
            "setup_lattice",
            [](PySession& s, py::handle lattice, py::kwargs fields) {
                json op = {{"op", "setup_lattice"}};
                if (!lattice.is_none() && fields.size() > 0)
                    throw SculptError("setup_lattice: give the settings as a dict or as keywords, not both");
                if (!lattice.is_none()) op["lattice"] = sp::toJson(lattice, "lattice");
                if (fields.size() > 0) op["lattice"] = sp::toJson(fields, "lattice");
                return s.run(sp::parseOp(op, "setup_lattice"), "setup_lattice");
            },
            py::arg("lattice") = py::none(),
            R"doc(Puts a fresh lattice around the current shape (an undoable operation); the deformation so far is kept.

lattice: the script's lattice object, or its fields as keywords (resolution=[12, 12, 12], degree=[3, 3, 3],
padding=0.05, pin_layers=0, region={"min": [...], "max": [...]}); neither: the current settings.)doc")
        .def(
            "undo", [](PySession& s) { return s.run(sp::parseOp({{"op", "undo"}}, "undo"), "undo"); },
            "Undoes the last operation (its inverse manipulation). Nothing to undo: status \"no-op\".")
        .def(
            "redo", [](PySession& s) { return s.run(sp::parseOp({{"op", "redo"}}, "redo"), "redo"); },
            "Redoes the next operation. Nothing to redo: status \"no-op\".")
        .def(
            "run",
            [](PySession& s, py::handle op) {
                const json opJson = sp::toJson(op, "op");
                const std::string name = opJson.is_object() && opJson.contains("op") && opJson["op"].is_string()
                                             ? opJson["op"].get<std::string>()
                                             : std::string("run");
                return s.run(sp::parseOp(opJson, name), name);
            },
            py::arg("op"),
            R"doc(Runs any one script op, given as its JSON object as a dict, e.g. {"op": "set_pins", "pin": [[3, 3, 3]]}
or {"op": "refine", "tolerance": 0.002}. Returns its report. A "screenshot" op uses the default picture
(1280 x 800, framed). begin_group / end_group belong to whole scripts; use {"op": "group", ...}.)doc")
        .def(
            "save",
            [](const PySession& s, const std::string& path) {
                std::vector<std::string> warnings;
                if (sculpt::Status st = sp::saveMeshFile(path, s.mesh, s.session, warnings); !st) throw SculptError("save: " + st.message);
                return warnings;
            },
            py::arg("path"),
            R"doc(Writes the current shape to path as the command line's --output does, in the format of the
extension (.obj .ply .stl .gltf .glb .off). A loaded OBJ keeps its text with only moved vertices and changed
normals rewritten; PLY, STL and glTF store single precision. Returns the warnings (a list of str) naming
what the format cannot hold (groups in PLY, colours in STL...). Atomic: on failure (sculpt.Error) the file
is left as it was.)doc")
        .def(
            "screenshot",
            [](const PySession& s, const std::string& path, py::handle size, py::handle camera, py::handle overlays,
               const std::string& glBackend) {
                const sculpt::app::CliOptions options = sp::screenshotOptions(size, camera, overlays, glBackend);
                if (sculpt::Status st = s.screenshot(path, options); !st) throw SculptError("screenshot: " + st.message);
            },
            py::arg("path"), py::kw_only(), py::arg("size") = py::make_tuple(1280, 800), py::arg("camera") = py::none(),
            py::arg("overlays") = py::tuple(), py::arg("gl_backend") = "auto",
            R"doc(Renders the current shape offscreen (OSMesa or EGL) to a PNG at path, as the command line's --screenshot.

size: (width, height) in pixels, 1 to 16384. camera: (yaw, pitch, distance): degrees, degrees, and the
distance from the framed centre in the mesh's units (> 0); None frames the mesh. overlays: any of
"jacobian", "affected", "lattice", "wireframe". Raises sculpt.Error when no GL context can be made or the
file cannot be written.)doc");

    m.def(
        "load",
        [](const std::string& path, py::handle lattice, py::handle injectivity, bool trackJacobian) {
            const sculpt::io::Script settings = sp::parseSettings(lattice, injectivity, "load");
            auto session = std::make_unique<PySession>();
            if (sculpt::Status s = sp::loadMeshFile(path, session->mesh, session->warnings); !s) throw SculptError("load: " + s.message);
            session->source = path;
            session->start(settings, trackJacobian, "load: " + path);
            return session;
        },
        py::arg("path"), py::kw_only(), py::arg("lattice") = py::none(), py::arg("injectivity") = py::none(),
        py::arg("track_jacobian") = false,
        R"doc(A session on the mesh file at path (.obj .ply .stl .gltf .glb .off, the format from the extension), as the
command line's --input.

lattice, injectivity, track_jacobian: as Session(V, F, ...). Raises sculpt.Error with the file and line of
what is wrong in the file; warnings go to Session.warnings.)doc");
    m.def(
        "default_mesh_path", []() { return sculpt::app::defaultMeshPath(nullptr); },
        "The bundled default mesh (assets/default.obj), the command line's mesh without --input.");
}
