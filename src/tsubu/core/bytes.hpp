// Values as bytes, for the messages between processes (a run split among processes, block
// steps shared among them): appended to a string and taken back in the same order, in this
// machine's representation (the processes of one job share it).
#pragma once
#include <cstddef>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>

namespace tsubu {

template <class T>
void put(std::string& out, const T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

// The value at bytes[at ...); `at` moves past it.
template <class T>
T take(std::string_view bytes, std::size_t& at) {
  static_assert(std::is_trivially_copyable_v<T>);
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof v);
  at += sizeof v;
  return v;
}

}  // namespace tsubu
