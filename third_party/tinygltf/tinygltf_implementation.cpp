// tinygltf's implementation, compiled from Debian's header (libtinygltf-dev's /usr/include/tiny_gltf.h) into
// this program instead of linked from libtinygltf.so: libdraco.so, which libassimp brings in, exports its own
// bundled copy of tinygltf's functions (another version, other struct layouts), and the dynamic linker bound
// our calls to those first (a double free on the first glTF read). Defined in the executable, these win over
// every shared library's. With the same configuration as every other includer of the header (its image
// functions call stb, whose implementation is Debian's libstb.so).
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
