// Lattice library files (*.lattice.json; Coquillart 1990, 3.1-3.2: lattices are tools kept in a library,
// apart from any mesh), without the JSON library: what the window and its tests need to read and write them.
// The format is described in io/lattice_json.h, which holds the JSON-level functions; both are defined in
// io/lattice_json.cpp.
#pragma once

#include <memory>
#include <string>

#include "core/status.h"
#include "core/volume/volume.h"

namespace sculpt::io {

// A library entry: a named lattice tool.
struct LatticeFile {
    std::string name;
    std::shared_ptr<const core::Volume> volume;  // any registered kind
};
// Reads a library file; the error names the file, the field and what is wrong; `out` untouched on failure.
Status readLatticeFile(const std::string& path, LatticeFile& out);
Status parseLatticeFile(const std::string& text, const std::string& displayName, LatticeFile& out);
// Writes it atomically (a failed save leaves an existing file as it was).
Status writeLatticeFile(const std::string& path, const LatticeFile& file);
std::string latticeFileText(const LatticeFile& file);

}  // namespace sculpt::io
