#pragma once
// Raw little-endian bytes for the binary writers (glTF buffers, AO outputs, generated inputs):
// every build target is little endian, so a value's bytes are its memory.
#include <cstring>
#include <string>
#include <type_traits>

namespace rtmini {

template <class T>
void append_raw(std::string& buf, const T& v) {
  static_assert(std::is_trivially_copyable<T>::value, "raw bytes only");
  char bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));
  buf.append(bytes, sizeof(T));
}

}  // namespace rtmini
