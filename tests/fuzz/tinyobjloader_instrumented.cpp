// tinyobjloader's implementation, compiled into the fuzz target only so that libFuzzer's coverage and
// AddressSanitizer reach inside it (the Debian shared library is uninstrumented). The library build
// (src/io) never defines TINYOBJLOADER_IMPLEMENTATION; it links libtinyobjloader_double.
#define TINYOBJLOADER_USE_DOUBLE
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
