// PNG files of 8-bit RGBA pixels (screenshots, golden images).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/status.h"

namespace sculpt::io {

// Writes width x height RGBA pixels (rgba: 4 * width * height bytes, rows top-down) to `path`.
// Atomic (io::writeFileAtomically): the encoded image goes to a temporary file in the same directory,
// which is fsync'ed and renamed over `path`, so a failed write (bad directory, full disk, bad size)
// never damages an existing file at `path`.
// Fails on width or height < 1, more than 2^28 pixels, a null rgba, or any I/O error, naming the path.
Status writePng(const std::string& path, int width, int height, const std::uint8_t* rgba);

// Reads any PNG stb_image understands, converted to RGBA (4 bytes per pixel, rows top-down).
// On failure the outputs are left unchanged.
Status readPng(const std::string& path, int& width, int& height, std::vector<std::uint8_t>& rgba);

}  // namespace sculpt::io
