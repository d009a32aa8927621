#include "src/geometry/mesh/ply_header.hpp"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "src/geometry/mesh/mesh_reader.hpp"

namespace ckpd {

namespace {

constexpr std::size_t kMaxHeaderBytes = std::size_t{1} << 20;

// The size in bytes of a PLY scalar type, 0 for a name that is none.
int type_bytes(const std::string& type) {
  static const std::map<std::string, int> sizes{
      {"char", 1},  {"uchar", 1},   {"int8", 1},   {"uint8", 1},  {"short", 2}, {"ushort", 2},
      {"int16", 2}, {"uint16", 2},  {"int", 4},    {"uint", 4},   {"int32", 4}, {"uint32", 4},
      {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
  const auto it = sizes.find(type);
  return it == sizes.end() ? 0 : it->second;
}

struct Element {
  std::string name;
  double count = 0;
  double binary_row = 0;  // the least bytes of a row in a binary file (a list counts its length)
  int values = 0;         // the values of a row at least (a list: its length)
};

}  // namespace

void check_ply_header(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MeshError("a readable PLY file (" + path + " cannot be opened)");
  std::string header;
  header.resize(kMaxHeaderBytes);
  in.read(header.data(), static_cast<std::streamsize>(header.size()));
  header.resize(static_cast<std::size_t>(in.gcount()));
  auto fail = [&](const std::string& expected) {
    throw MeshError("a PLY file with " + expected + " (" + path + ")");
  };
  if (header.rfind("ply\n", 0) != 0 && header.rfind("ply\r\n", 0) != 0)
    fail("'ply' on its first line");
  std::size_t end = std::string::npos;
  for (std::size_t at = header.find("end_header"); at != std::string::npos;
       at = header.find("end_header", at + 1)) {
    const std::size_t eol = header.find('\n', at);
    if (header[at - 1] == '\n' && eol != std::string::npos &&
        header.find_first_not_of(" \t\r", at + 10) == eol) {
      end = eol + 1;
      break;
    }
  }
  if (end == std::string::npos)
    fail("a header that ends in an end_header line within its first " +
         std::to_string(kMaxHeaderBytes >> 20) + " MiB (the file has " +
         std::to_string(header.size()) + " bytes and no such line: is it cut short?)");
  std::istringstream lines(header.substr(0, end));
  std::string line, format;
  std::vector<Element> elements;
  int number = 0;
  while (std::getline(lines, line)) {
    ++number;
    std::istringstream words(line);
    std::string word;
    words >> word;
    const std::string where = " (header line " + std::to_string(number) + ": '" + line + "')";
    if (word == "format") {
      words >> format;
      if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
        fail("format ascii, binary_little_endian or binary_big_endian" + where);
    } else if (word == "element") {
      Element e;
      std::string count;
      words >> e.name >> count;
      if (e.name.empty() || count.empty() ||
          count.find_first_not_of("0123456789") != std::string::npos || count.size() > 19)
        fail("'element NAME COUNT' lines with a whole COUNT" + where);
      e.count = std::stod(count);
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) fail("each property after its element" + where);
      std::string type;
      words >> type;
      int bytes = 0;
      if (type == "list") {
        std::string count_type, item_type;
        words >> count_type >> item_type;
        bytes = type_bytes(count_type);
        if (bytes == 0 || type_bytes(item_type) == 0)
          fail("'property list COUNT_TYPE ITEM_TYPE NAME' with PLY types" + where);
      } else {
        bytes = type_bytes(type);
        if (bytes == 0)
          fail("'property TYPE NAME' with a PLY type (float, int, uchar, ...)" + where);
      }
      elements.back().binary_row += bytes;
      elements.back().values += 1;
    }
  }
  if (format.empty()) fail("a format line");
  // The least bytes the elements take after the header: in ASCII each value is a character and
  // a separator, in binary its type's size.
  double least = 0;
  for (const Element& e : elements)
    least += e.count * (format == "ascii" ? 2.0 * e.values : e.binary_row);
  if (format == "ascii" && least > 0) least -= 1;  // the last value needs no separator
  const double after = static_cast<double>(std::filesystem::file_size(path) - end);
  if (least > after) {
    std::ostringstream s;
    s << "element counts that fit in the file (";
    for (std::size_t k = 0; k < elements.size(); ++k)
      s << (k ? ", " : "") << static_cast<std::uint64_t>(elements[k].count) << " "
        << elements[k].name;
    s << " need at least " << least << " bytes after the header, the file has " << after
      << ": is it cut short?)";
    fail(s.str());
  }
}

}  // namespace ckpd
