// tinygltf's implementation, compiled here with the sanitizers and the fuzzer's coverage (the
// main build links Debian's shared libtinygltf instead). No image codecs: rtmini never decodes
// images through tinygltf (gltf_reader.cpp installs a loader that skips them).
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
