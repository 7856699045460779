// Lattice tools as JSON (Coquillart 1990, 3.1-3.2: lattices are tools kept in a library, apart from any
// mesh). One format serves the library files (*.lattice.json), the scripts' "lattice" objects and the
// recordings (docs/lattices.md).
//
// A lattice object is either a predefined shape, decided when read:
//   {"kind": "parallelepiped", "origin": [x,y,z], "edges": [[..],[..],[..]], "chunks": [3], "degree": [3]}
//   {"kind": "cylinder", "base": [..], "axis": [..], "radius": r, "height": h, "chunks": [radial, angular, axial],
//    "degree": [radial, axial]}
//   {"kind": "sphere", "centre": [..], "axis": [..], "radius": r, "chunks": [radial, angular, polar], "degree": d}
//   {"kind": "prism", "profile": {"min": [u,v], "max": [u,v], "chunks": [2], "degree": [2], "points": [[u,v],..]?},
//    "origin": [..], "u_axis": [..], "v_axis": [..], "direction": [..], "chunks": n, "degree": d}
//   {"kind": "loft", "profile": {... as prism's ...}, "sections": [section, ...], "degree": d (2)}: a prism lofted
//    through its sections (3.1.4, the "S" of Fig. 8), which are the control points along w (at least d + 1,
//    at most 64); each section is the profile placed by hand, {"origin": [..], "u_axis": [..] (x), "v_axis":
//    [..] (y), "scale": s or [s_u, s_v] (1)}: world point = origin + s_u p_u u + s_v p_v v with u, v
//    orthonormalised (v made orthogonal to u), or its count_u x count_v world points [[x,y,z], ...]. The
//    sections must advance along u x v (a right-handed lattice).
// or an explicit net, which is how every lattice is written (exact: doubles in shortest round-trip form):
//   {"kind": "net", "shape": "cylinder", "count": [3], "degree": [3], "multiplicity": [3],
//    "points": [[x,y,z], ...], "weights": [...], "welds": [[slot, slot, ...], ...],
//    "knots": [[...], [], [...]]}: "knots" (optional) gives an axis a general clamped knot vector (count + degree
//    + 1 non-decreasing values from degree+1 zeros to degree+1 ones, interior multiplicity <= degree), as knot
//    insertion at a chosen parameter makes; [] or no "knots" means the uniform knots of count, degree and
//    multiplicity. Written only when some axis is not uniform.
// A library file wraps one lattice: {"format": "dmffd-lattice", "version": 1, "name": "...", "lattice": {...}}.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/volume/lattice_net.h"
#include "core/status.h"
#include "io/lattice_file.h"

namespace sculpt::io {

// Parses a lattice object (either form). Errors name the field path under `path` and what was expected.
Status parseLatticeNetJson(const nlohmann::json& j, const std::string& path, core::LatticeNet& out);
// The explicit form of a net.
nlohmann::json latticeNetJson(const core::LatticeNet& net);

// The library files (LatticeFile, readLatticeFile, writeLatticeFile) are declared in io/lattice_file.h.

// ---- volume kinds (core/volume/volume.h) -------------------------------------------------------------------------
// Every lattice kind has a JSON form; a kind added to the engine registers its reader and writer here, and
// the scripts, recordings and library files then carry it with no other change. LatticeNet (every "kind"
// above) is registered from the start.
struct VolumeFormat {
    std::vector<std::string> kinds;  // the "kind" values it reads
    // Parses a lattice object of one of those kinds; errors name the field path under `path`.
    std::function<Status(const nlohmann::json& j, const std::string& path, std::shared_ptr<const core::Volume>& out)> read;
    // Writes the volume if it is of this format's kind (returns false otherwise).
    std::function<bool(const core::Volume& volume, nlohmann::json& out)> write;
};
void registerVolumeFormat(VolumeFormat format);
// Parses a lattice object of any registered kind ("kind" selects the format). On failure `out` is untouched.
Status parseVolumeJson(const nlohmann::json& j, const std::string& path, std::shared_ptr<const core::Volume>& out);
// The explicit JSON form of a volume of any registered kind (a tensor net: latticeNetJson). Throws
// std::invalid_argument for a kind no format writes (a programming error: every kind registers one).
nlohmann::json volumeJson(const core::Volume& volume);

}  // namespace sculpt::io
