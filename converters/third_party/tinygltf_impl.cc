// The one translation unit that compiles tinygltf's implementation (Debian's
// tiny_gltf.h is header-only). Built with hidden visibility into a static
// library so that it never mixes with the copy libdraco.so exports.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
