#include "src/geometry/mesh/mesh_reader.hpp"

#include <assimp/importerdesc.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <assimp/Importer.hpp>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <unordered_map>

#include "src/geometry/mesh/ply_header.hpp"

#if defined(__has_feature)
#define CKPD_HAS_ADDRESS_SANITIZER __has_feature(address_sanitizer)
#else
#define CKPD_HAS_ADDRESS_SANITIZER 0
#endif

namespace ckpd {

void TriangleMesh::bounds(Vec3& lo, Vec3& hi) const {
  lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (const Vec3& v : vertex) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
}

namespace {

// Exact float positions as a key: the same float triple from two facets is one vertex.
struct PositionKey {
  std::uint32_t bits[3];
  bool operator==(const PositionKey& o) const {
    return bits[0] == o.bits[0] && bits[1] == o.bits[1] && bits[2] == o.bits[2];
  }
};
struct PositionHash {
  std::size_t operator()(const PositionKey& k) const {
    return (std::size_t{k.bits[0]} * 73856093u) ^ (std::size_t{k.bits[1]} * 19349663u) ^
           (std::size_t{k.bits[2]} * 83492791u);
  }
};

PositionKey key_of(const aiVector3D& v) {
  PositionKey k;
  const float c[3] = {v.x == 0 ? 0.0f : v.x, v.y == 0 ? 0.0f : v.y,
                      v.z == 0 ? 0.0f : v.z};  // -0 and +0 are one position
  for (int d = 0; d < 3; ++d) std::memcpy(&k.bits[d], &c[d], sizeof(float));
  return k;
}

// Runs in the child process (read_mesh_file): assimp's import and the welding.
TriangleMesh import_mesh(const std::string& path) {
  Assimp::Importer importer;
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                  aiProcess_PreTransformVertices);
  if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw MeshError(
        "a mesh file assimp can parse (assimp: " + std::string(importer.GetErrorString()) + ")");
  TriangleMesh mesh;
  std::unordered_map<PositionKey, std::uint32_t, PositionHash> index;
  std::size_t others = 0;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* am = scene->mMeshes[m];
    std::vector<std::uint32_t> welded(am->mNumVertices);
    for (unsigned v = 0; v < am->mNumVertices; ++v) {
      const aiVector3D& p = am->mVertices[v];
      const auto [it, fresh] =
          index.try_emplace(key_of(p), static_cast<std::uint32_t>(mesh.vertex.size()));
      if (fresh) mesh.vertex.emplace_back(p.x, p.y, p.z);
      welded[v] = it->second;
    }
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& face = am->mFaces[f];
      if (face.mNumIndices != 3) {
        ++others;  // points and lines
        continue;
      }
      mesh.triangle.push_back(
          {welded[face.mIndices[0]], welded[face.mIndices[1]], welded[face.mIndices[2]]});
    }
  }
  if (mesh.triangle.empty())
    throw MeshError("a mesh with triangles (the file holds " + std::to_string(mesh.vertex.size()) +
                    " vertices and " + std::to_string(others) + " points or lines but no faces)");
  return mesh;
}

// The child's answer on the pipe: 'M', counts, vertices, triangles; or 'E' and a message.
void write_all(int fd, const void* data, std::size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = write(fd, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) _exit(3);
    p += n;
    size -= static_cast<std::size_t>(n);
  }
}

[[noreturn]] void run_child(const std::string& path, int fd) {
  // The limits: a runaway importer (invalid/OutOfMemory.off drove RSS past 8 GB in 20 s) is
  // stopped by the kernel, and the parent reports it.
  rlimit cpu{kMeshImportCpuSeconds, kMeshImportCpuSeconds + 1};
  setrlimit(RLIMIT_CPU, &cpu);
#if !defined(__SANITIZE_ADDRESS__) && !CKPD_HAS_ADDRESS_SANITIZER
  // (AddressSanitizer reserves terabytes of address space: no limit under it.)
  rlimit memory{kMeshImportMemoryBytes, kMeshImportMemoryBytes};
  setrlimit(RLIMIT_AS, &memory);
#endif
  if (const char* hook = std::getenv("CKPD_TEST_MESH_IMPORT_ABORT"); hook && *hook == '1')
    std::abort();  // tests: an importer that aborts, as assimp's ai_assert does
  try {
    const TriangleMesh mesh = import_mesh(path);
    const std::uint64_t counts[2] = {mesh.vertex.size(), mesh.triangle.size()};
    write_all(fd, "M", 1);
    write_all(fd, counts, sizeof counts);
    write_all(fd, mesh.vertex.data(), mesh.vertex.size() * sizeof(Vec3));
    write_all(fd, mesh.triangle.data(), mesh.triangle.size() * sizeof(mesh.triangle[0]));
  } catch (const MeshError& e) {
    const std::string text = e.what();
    write_all(fd, "E", 1);
    write_all(fd, text.data(), text.size());
  } catch (const std::bad_alloc&) {
    const std::string text = "the importer ran out of its memory limit of " +
                             std::to_string(kMeshImportMemoryBytes >> 30) + " GiB";
    write_all(fd, "X", 1);
    write_all(fd, text.data(), text.size());
  }
  close(fd);
  _exit(0);
}

std::string signal_text(int signal) {
  const char* name = strsignal(signal);
  std::string text = "signal " + std::to_string(signal) + " (" + (name ? name : "unknown") + ")";
  if (signal == SIGXCPU)
    text += ": over the CPU time limit of " + std::to_string(kMeshImportCpuSeconds) + " s";
  return text;
}

}  // namespace

TriangleMesh read_mesh_file(const std::string& path) {
  if (!std::filesystem::is_regular_file(path))
    throw MeshError("a mesh file (" + path + " does not exist or is not a file)");
  std::string importer_name = "assimp";
  {
    Assimp::Importer importer;
    const std::string extension = std::filesystem::path(path).extension().string();
    if (extension.empty() || !importer.IsExtensionSupported(extension))
      throw MeshError("a mesh format that assimp reads (the file name ends in '" + extension +
                      "'; known: .stl .obj .ply .off .gltf .glb .fbx .dae .3ds and more)");
    const std::size_t index = importer.GetImporterIndex(extension.c_str());
    if (const aiImporterDesc* desc = importer.GetImporterInfo(index); desc && desc->mName)
      importer_name = std::string("assimp's ") + desc->mName;
  }
  // Checked before reading: a 6 GiB sparse STL was read whole.
  const std::uintmax_t size = std::filesystem::file_size(path);
  if (size > kMaxMeshFileBytes)
    throw MeshError("a mesh file of at most " + std::to_string(kMaxMeshFileBytes >> 20) + " MiB (" +
                    path + " has " + std::to_string(size >> 20) + " MiB)");
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".ply") check_ply_header(path);  // a cut header kept assimp busy 2 minutes

  // The import runs in a child process: an importer that crashes, aborts or runs away (all
  // seen with assimp on malformed files) ends the child, not ckpd, and becomes an error here.
  int fds[2];
  if (pipe(fds) != 0)
    throw MeshError("a pipe for the mesh import (" + std::string(strerror(errno)) + ")");
  const pid_t child = fork();
  if (child < 0) {
    close(fds[0]);
    close(fds[1]);
    throw MeshError("a child process for the mesh import (" + std::string(strerror(errno)) + ")");
  }
  if (child == 0) {
    close(fds[0]);
    run_child(path, fds[1]);
  }
  close(fds[1]);
  std::string answer;
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = read(fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    answer.append(buffer, static_cast<std::size_t>(n));
  }
  close(fds[0]);
  int status = 0;
  while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  // assimp's names mostly end in "Importer" already ("Raw Importer"): not "Importer importer".
  const bool named = importer_name.size() >= 8 &&
                     importer_name.compare(importer_name.size() - 8, 8, "Importer") == 0;
  const std::string who = named ? importer_name : importer_name + " importer";
  if (WIFSIGNALED(status))
    throw MeshError("a mesh file " + who + " can read: it was killed by " +
                    signal_text(WTERMSIG(status)) + " reading " + path);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || answer.empty())
    throw MeshError("a mesh file " + who + " can read: it stopped with exit status " +
                    std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + " reading " +
                    path);
  if (answer[0] == 'E') throw MeshError(answer.substr(1));
  if (answer[0] == 'X') throw MeshError("a mesh file " + who + " can read: " + answer.substr(1));
  std::uint64_t counts[2] = {0, 0};
  if (answer.size() < 1 + sizeof counts) throw MeshError("a complete answer from the " + who);
  std::memcpy(counts, answer.data() + 1, sizeof counts);
  TriangleMesh mesh;
  // The counts bounded by the answer's length first: their products cannot wrap.
  const std::size_t body = answer.size() - 1 - sizeof counts;
  if (counts[0] > body / sizeof(Vec3) || counts[1] > body / sizeof(mesh.triangle[0]) ||
      counts[0] * sizeof(Vec3) + counts[1] * sizeof(mesh.triangle[0]) != body)
    throw MeshError("a complete answer from the " + who);
  mesh.vertex.resize(counts[0]);
  mesh.triangle.resize(counts[1]);
  const char* at = answer.data() + 1 + sizeof counts;
  std::memcpy(static_cast<void*>(mesh.vertex.data()), at, counts[0] * sizeof(Vec3));
  std::memcpy(mesh.triangle.data(), at + counts[0] * sizeof(Vec3),
              counts[1] * sizeof(mesh.triangle[0]));
  for (const auto& t : mesh.triangle)
    for (std::uint32_t v : t)
      if (v >= counts[0]) throw MeshError("a consistent answer from the " + who);
  return mesh;
}

}  // namespace ckpd
