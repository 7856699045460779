#include "app/window/lattice_commands.h"

#include "core/volume/volume_kinds.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <set>
#include <system_error>

#include <Eigen/Geometry>

#include "app/cli_options.h"
#include "app/file_browser.h"
#include "app/window/picking.h"
#include "io/script.h"
#include "core/tspline/tspline_view.h"
#include "io/lattice_file.h"
#include "render/camera.h"

namespace sculpt::app {
namespace {

namespace fs = std::filesystem;

bool readEntry(const std::string& path, LatticeLibraryEntry& entry, std::string& error) {
    io::LatticeFile file;
    if (Status s = io::readLatticeFile(path, file); !s) {
        error = s.message;
        return false;
    }
    entry.path = path;
    entry.name = file.name.empty() ? fs::path(path).stem().stem().string() : file.name;
    entry.volume = std::move(file.volume);
    return true;
}

}  // namespace

void reportLatticeOperation(AppState& state, const core::OpReport& report, const Status& status, const std::string& done,
                            bool show) {
    if (status && report.status == core::OpStatus::Applied) {
        noteSessionMoved(state);
        if (show && !latticeShown(state)) {
            Overlays overlays = state.overlays;
            overlaysOfTool(overlays, state.tools.mode).lattice = true;
            setOverlays(state, overlays);
        }
        state.hasReport = true;
        state.lastReport = report;
        state.stats.solveMs = report.wallMs;
        setStatus(state, done + (report.reason.empty() ? std::string(".") : ": " + report.reason + "."), false);
    } else {
        reportOperation(state, report, status);
    }
    state.gpu.fields = true;
}

std::string latticeLibraryFolder() { return (fs::path(defaultMeshPath(nullptr)).parent_path() / "lattices").string(); }

std::string userLatticeFolder() {
    const char* data = std::getenv("XDG_DATA_HOME");
    fs::path base;
    // note: the XDG spec says a relative XDG_DATA_HOME is invalid and to be ignored.
    if (data && *data && fs::path(data).is_absolute()) {
        base = data;
    } else {
        const char* home = std::getenv("HOME");
        if (!home || !*home) return {};
        base = fs::path(home) / ".local" / "share";
    }
    return (base / "dmffd-sculpt" / "lattices").lexically_normal().string();
}

bool inShippedLatticeLibrary(const std::string& path) {
    std::error_code ec;
    const fs::path shipped = fs::weakly_canonical(latticeLibraryFolder(), ec);
    if (ec) return false;
    const fs::path folder = fs::weakly_canonical(fs::absolute(path, ec).parent_path(), ec);
    return !ec && folder == shipped;
}

std::string latticeNameOfPath(const std::string& path) {
    std::string name = fileNameOfPath(path);
    const std::string extension = ".lattice.json";
    if (hasExtension(name, {extension})) name.resize(name.size() - extension.size());
    return name;
}

std::string freshLatticeName(const AppState& state, const std::string& toolName, const std::string& folder) {
    std::string wanted = toolName.empty() ? std::string("lattice") : toolName;
    std::replace(wanted.begin(), wanted.end(), '/', '-');
    std::replace(wanted.begin(), wanted.end(), '\\', '-');
    const std::vector<LatticeLibraryEntry>& library = state.lattices.library;
    const auto taken = [&](const std::string& name) {
        std::error_code ec;
        return std::any_of(library.begin(), library.end(), [&](const LatticeLibraryEntry& e) { return e.name == name; }) ||
               fs::exists(fs::path(folder) / (name + ".lattice.json"), ec);
    };
    if (!taken(wanted)) return wanted;
    // "cylinder 2" counts on from 2; "cylinder" starts at 2.
    std::string base = wanted;
    int number = 1;
    const size_t space = wanted.find_last_of(' ');
    if (space != std::string::npos && space + 1 < wanted.size() && space + 10 > wanted.size() &&
        std::all_of(wanted.begin() + static_cast<std::ptrdiff_t>(space) + 1, wanted.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        base = wanted.substr(0, space);
        number = std::stoi(wanted.substr(space + 1));
    }
    for (int n = number + 1;; ++n) {
        const std::string candidate = base + " " + std::to_string(n);
        if (!taken(candidate)) return candidate;
    }
}

void loadLatticeLibraries(AppState& state) {
    loadLatticeLibrary(state, latticeLibraryFolder());
    const std::string user = userLatticeFolder();
    if (!user.empty()) loadLatticeLibrary(state, user);
}

void loadLatticeLibrary(AppState& state, const std::string& folder) {
    LatticesPanelState& panel = state.lattices;
    panel.libraryLoaded = true;
    std::set<std::string> paths;
    std::error_code ec;
    for (const fs::directory_entry& item : fs::directory_iterator(folder, ec))
        if (item.is_regular_file(ec) && hasExtension(item.path().filename().string(), {".lattice.json"}))
            paths.insert(item.path().string());
    std::vector<std::string> failed;
    for (const std::string& path : paths) {
        if (std::any_of(panel.library.begin(), panel.library.end(), [&](const LatticeLibraryEntry& e) { return e.path == path; }))
            continue;
        LatticeLibraryEntry entry;
        std::string error;
        if (readEntry(path, entry, error)) panel.library.push_back(std::move(entry));
        else failed.push_back(error);
    }
    if (!failed.empty()) setStatus(state, "Lattice library: " + failed.front(), true);
}

bool openLatticeFile(AppState& state, const std::string& path) {
    LatticeLibraryEntry entry;
    std::string error;
    if (!readEntry(path, entry, error)) {
        setStatus(state, "Cannot open the lattice: " + error, true);
        return false;
    }
    LatticesPanelState& panel = state.lattices;
    const auto same = std::find_if(panel.library.begin(), panel.library.end(), [&](const LatticeLibraryEntry& e) { return e.path == path; });
    const int at = static_cast<int>(same - panel.library.begin());  // note: before a push_back moves the entries
    if (same != panel.library.end()) *same = entry;
    else panel.library.push_back(entry);
    panel.libraryChoice = at;
    setStatus(state, "Lattice " + entry.name + " (" + describeLattice(*entry.volume) + ") is in the library: Add or Place it.", false);
    return true;
}

void addLatticeFromLibrary(AppState& state, int entry) {
    if (state.drag.active) return;
    const std::vector<LatticeLibraryEntry>& library = state.lattices.library;
    if (entry < 0 || entry >= static_cast<int>(library.size())) {
        setStatus(state, "Choose a lattice of the library first.", true);
        return;
    }
    core::OpReport report;
    const Status s = state.session.tools().add({library[static_cast<size_t>(entry)].name, library[static_cast<size_t>(entry)].volume}, report);
    if (s && report.status == core::OpStatus::Applied)
        state.lattices.selectedTool = static_cast<int>(state.session.tools().list().size()) - 1;
    reportLatticeOperation(state, report, s, "Added lattice " + library[static_cast<size_t>(entry)].name);
}

void placeLatticeCommand(AppState& state, const core::Volume& volume, const std::string& name, int editIndex,
                         const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size) {
    if (state.drag.active) return;
    std::shared_ptr<const core::Volume> placed;
    if (Status s = core::placeVolume(volume, point, normal, size, placed); !s) {
        setStatus(state, "Lattice not placed: " + s.message, true);
        return;
    }
    core::LatticeTool tool{name, std::move(placed)};
    core::OpReport report;
    const Status s = editIndex < 0 ? state.session.tools().add(tool, report) : state.session.tools().edit(editIndex, tool, report);
    if (s && report.status == core::OpStatus::Applied)
        state.lattices.selectedTool = editIndex < 0 ? static_cast<int>(state.session.tools().list().size()) - 1 : editIndex;
    reportLatticeOperation(state, report, s, (editIndex < 0 ? "Placed lattice " : "Moved lattice ") + name);
}

void freezeLatticeCommand(AppState& state, int index, int pinLayers) {
    if (state.drag.active) return;
    core::OpReport report;
    const Status s = state.session.tools().freeze(index, std::clamp(pinLayers, 0, 2), report);
    state.tools.lattice.points.clear();
    reportLatticeOperation(state, report, s, "Froze the lattice", true);
}

void unfreezeLatticeCommand(AppState& state) {
    if (state.drag.active) return;
    core::OpReport report;
    const Status s = state.session.tools().unfreeze(report);
    state.tools.lattice.points.clear();
    reportLatticeOperation(state, report, s, "Unfroze the lattice: the shape stays, the box lattice is back");
}

void removeLatticeToolCommand(AppState& state, int index) {
    if (state.drag.active) return;
    const std::vector<core::LatticeTool>& tools = state.session.tools().list();
    const std::string name = index >= 0 && index < static_cast<int>(tools.size()) ? tools[static_cast<size_t>(index)].name : std::string();
    core::OpReport report;
    const Status s = state.session.tools().remove(index, report);
    if (s && report.status == core::OpStatus::Applied)
        state.lattices.selectedTool = std::min(state.lattices.selectedTool, static_cast<int>(state.session.tools().list().size()) - 1);
    reportLatticeOperation(state, report, s, "Removed lattice " + name);
}

void editLatticeNetCommand(AppState& state, int index, const std::vector<core::NetEdit>& edits, const std::string& what) {
    if (state.drag.active) return;
    io::ScriptOp op;
    op.kind = io::ScriptOp::Kind::EditLattice;
    op.toolIndex = index;
    op.netEdits = edits;
    core::OpReport report;
    const Status s = io::runScriptOp(state.session, op, report);
    reportLatticeOperation(state, report, s, what);
}

Status saveLatticeToolCommand(AppState& state, int index, const std::string& path, const std::string& name) {
    const std::vector<core::LatticeTool>& tools = state.session.tools().list();
    if (index < 0 || index >= static_cast<int>(tools.size()) || !tools[static_cast<size_t>(index)].volume) {
        const Status error = Status::error("there is no lattice " + std::to_string(index));
        setStatus(state, "Lattice not saved: " + error.message, true);
        return error;
    }
    if (inShippedLatticeLibrary(path)) {
        const std::string user = userLatticeFolder();
        const Status error = Status::error("the shipped lattices are never replaced; save yours in " +
                                           (user.empty() ? std::string("another folder") : user));
        setStatus(state, "Lattice not saved: " + error.message + ".", true);
        return error;
    }
    const core::LatticeTool& tool = tools[static_cast<size_t>(index)];
    const std::string saved = name.empty() ? tool.name : name;
    if (Status s = io::writeLatticeFile(path, {saved, tool.volume}); !s) {
        setStatus(state, "Lattice not saved (the file on disk is as it was): " + s.message, true);
        return s;
    }
    // In the library at once, as the file now is (a file replaced through "Replace?" keeps its one entry).
    std::vector<LatticeLibraryEntry>& library = state.lattices.library;
    LatticeLibraryEntry entry{path, saved, tool.volume};
    const auto same = std::find_if(library.begin(), library.end(), [&](const LatticeLibraryEntry& e) { return e.path == path; });
    if (same != library.end()) *same = std::move(entry);
    else library.push_back(std::move(entry));
    setStatus(state, "Saved lattice " + saved + " to " + path + "; it is in the library.", false);
    return Status::success();
}

double placementSize(const AppState& state) {
    const Positions& p = state.session.mesh().positions;
    if (p.rows() == 0) return 1.0;
    const double diagonal = (p.colwise().maxCoeff() - p.colwise().minCoeff()).norm();
    return std::max(state.lattices.placeSizeFraction, 1e-3) * (diagonal > 0.0 ? diagonal : 1.0);
}

void beginPlacingLattice(AppState& state, LatticesPanelState::Placing what) {
    state.lattices.placing = what;
    setStatus(state, "Click on the mesh to place the lattice there (aligned with the surface). Esc cancels.", false);
}

void cancelPlacingLattice(AppState& state) {
    if (state.lattices.placing == LatticesPanelState::Placing::None) return;
    state.lattices.placing = LatticesPanelState::Placing::None;
    setStatus(state, "Placing cancelled.", false);
}

bool placeLatticeAtPixel(AppState& state, double x, double y) {
    LatticesPanelState& panel = state.lattices;
    if (panel.placing == LatticesPanelState::Placing::None || state.session.mesh().empty()) return false;
    Ray ray;
    if (!rayThroughPixel(state.camera, state.framebufferWidth, state.framebufferHeight, x, y, ray)) return true;
    const Positions& positions = state.session.mesh().positions;
    const Triangles& triangles = state.session.mesh().triangles;
    const SurfaceHit hit = intersectMesh(ray, positions, triangles);
    if (hit.triangle < 0) {
        setStatus(state, "Click on the mesh to place the lattice (Esc cancels).", true);
        return true;
    }
    const Eigen::Vector3d p0 = positions.row(triangles(hit.triangle, 0)).transpose();
    Eigen::Vector3d normal = (positions.row(triangles(hit.triangle, 1)).transpose() - p0)
                                 .cross(positions.row(triangles(hit.triangle, 2)).transpose() - p0);
    // note: the side the user clicked on faces the camera, whatever the triangle's winding.
    if (normal.dot(ray.direction) > 0.0) normal = -normal;
    const LatticesPanelState::Placing what = panel.placing;
    panel.placing = LatticesPanelState::Placing::None;
    if (what == LatticesPanelState::Placing::LibraryEntry) {
        if (panel.libraryChoice < 0 || panel.libraryChoice >= static_cast<int>(panel.library.size())) return true;
        const LatticeLibraryEntry& entry = panel.library[static_cast<size_t>(panel.libraryChoice)];
        placeLatticeCommand(state, *entry.volume, entry.name, -1, hit.point, normal, placementSize(state));
    } else {
        const std::vector<core::LatticeTool>& tools = state.session.tools().list();
        if (panel.selectedTool < 0 || panel.selectedTool >= static_cast<int>(tools.size())) return true;
        const core::LatticeTool tool = tools[static_cast<size_t>(panel.selectedTool)];
        placeLatticeCommand(state, *tool.volume, tool.name, panel.selectedTool, hit.point, normal, placementSize(state));
    }
    return true;
}

std::string describeLattice(const core::Volume& volume) {
    if (const core::TSplineVolume* tspline = core::asTSpline(&volume)) {
        // Song & Yang 2005: cells and their octree levels, and the two weights of sec. 4.
        const std::vector<core::TLatticeCell>& cells = tspline->lattice().cells;
        const auto [low, high] = std::minmax_element(cells.begin(), cells.end(), [](const auto& a, const auto& b) { return a.level < b.level; });
        const auto [light, heavy] = std::minmax_element(volume.controlWeights().begin(), volume.controlWeights().end());
        char weights[64];
        if (*light == *heavy) std::snprintf(weights, sizeof weights, "all weights %g", *light);
        else std::snprintf(weights, sizeof weights, "weights %g to %g", *light, *heavy);
        const std::string levels = low->level == high->level ? "level " + std::to_string(low->level)
                                                             : "levels " + std::to_string(low->level) + "-" + std::to_string(high->level);
        return "weighted T-spline, " + std::to_string(cells.size()) + " cells (" + levels + "), " +
               std::to_string(volume.controlPointCount()) + " control points, " + weights;
    }
    const core::LatticeNet* tensor = volume.tensorNet();
    if (!tensor) {
        size_t distinct = static_cast<size_t>(volume.controlPointCount());
        for (const std::vector<int>& group : volume.weldGroupList()) distinct -= group.size() - 1;
        return volume.kindName() + ", " + std::to_string(volume.controlPointCount()) + " points (" + std::to_string(distinct) +
               " after welds), " + std::to_string(volume.chunkCount()) + " chunks";
    }
    const core::LatticeNet& net = *tensor;
    size_t distinct = static_cast<size_t>(net.slotCount());
    for (const std::vector<int>& group : net.weldGroups) distinct -= group.size() - 1;
    std::string text = net.kind + ", " + std::to_string(net.count[0]) + " x " + std::to_string(net.count[1]) + " x " +
                       std::to_string(net.count[2]) + " points";
    if (distinct != static_cast<size_t>(net.slotCount())) text += " (" + std::to_string(distinct) + " after welds)";
    return text + ", degree " + std::to_string(net.degree[0]) + "/" + std::to_string(net.degree[1]) + "/" + std::to_string(net.degree[2]);
}

}  // namespace sculpt::app
