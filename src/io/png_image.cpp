#include "io/png_image.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include "io/atomic_file.h"

namespace sculpt::io {

namespace {

void appendToString(void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
}

}  // namespace

Status writePng(const std::string& path, int width, int height, const std::uint8_t* rgba) {
    if (width < 1 || height < 1)
        return Status::error("cannot write " + path + ": image size " + std::to_string(width) + " x " +
                             std::to_string(height) + " is empty");
    if (rgba == nullptr) return Status::error("cannot write " + path + ": no pixels given");
    // note: stb computes buffer sizes in int; 2^28 pixels (1 GiB of RGBA) keeps them far from overflow.
    if (std::int64_t(width) * height > (std::int64_t(1) << 28))
        return Status::error("cannot write " + path + ": image size " + std::to_string(width) + " x " +
                             std::to_string(height) + " is too large");
    // Encode in memory, then let writeFileAtomically put it in place (temporary file, fsync, rename).
    // note: stbi_flip_vertically_on_write is global state, so the caller provides rows top-down instead.
    std::string encoded;
    if (!stbi_write_png_to_func(appendToString, &encoded, width, height, 4, rgba, width * 4))
        return Status::error("cannot write " + path + ": PNG encoding failed");
    return writeFileAtomically(path, encoded);
}

Status readPng(const std::string& path, int& width, int& height, std::vector<std::uint8_t>& rgba) {
    int w = 0, h = 0, channels = 0;
    stbi_uc* pixels = stbi_load(path.c_str(), &w, &h, &channels, 4);
    if (!pixels) {
        const char* reason = stbi_failure_reason();
        return Status::error("cannot read " + path + ": " + (reason ? reason : "unknown error"));
    }
    rgba.assign(pixels, pixels + size_t(w) * size_t(h) * 4);
    stbi_image_free(pixels);
    width = w;
    height = h;
    return Status::success();
}

}  // namespace sculpt::io
