#pragma once
// FNV-1a (64 bit) over a sequence of bytes, values and texts: the content hashes of checkpoints
// and field frames. Each step is a bijection of the running value, so any change of a single
// byte changes the result; a corrupted file that HDF5 still reads is refused by it.
#include <cstddef>
#include <cstdint>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

namespace ckpd {

class ContentHash {
 public:
  void bytes(const void* data, std::size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      h_ ^= p[i];
      h_ *= 1099511628211ull;
    }
  }
  template <class T>
  void value(const T& v) {
    bytes(&v, sizeof v);
  }
  template <class T>
  void vector(const std::vector<T>& v) {
    value(v.size());
    bytes(v.data(), v.size() * sizeof(T));
  }
  void text(const std::string& s) {
    value(s.size());
    bytes(s.data(), s.size());
  }
  std::uint64_t value() const { return h_; }
  std::string hex() const { return hex(h_); }
  static std::string hex(std::uint64_t v) {
    std::ostringstream s;
    s << std::hex << std::setw(16) << std::setfill('0') << v;
    return s.str();
  }

 private:
  std::uint64_t h_ = 1469598103934665603ull;
};

}  // namespace ckpd
