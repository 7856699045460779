// File format cases of sculpt_bench (io/mesh_file.h):
//   load_ply_1m      loading a binary little-endian PLY of 1M vertices (with RGBA colours) and 2M triangles
//   save_ply_1m      saving it (binary, deformed positions)
//   load_ascii_ply_1m, load_stl_1m, load_glb_1m   the same surface as ASCII PLY, binary STL and GLB
#pragma once

#include <string>
#include <vector>

namespace sculpt::bench {

void runIoBenchmarks(const std::vector<std::string>& filters = {});

}  // namespace sculpt::bench
