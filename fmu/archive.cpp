#include "archive.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zip.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <vector>

#include "fmu_error.hpp"

namespace railcosim::fmu {
namespace {

namespace fs = std::filesystem;

struct ZipCloser {
  void operator()(zip_t* z) const { zip_discard(z); }
};
struct ZipFileCloser {
  void operator()(zip_file_t* f) const { zip_fclose(f); }
};

// One entry, checked: where it lands inside the folder and what it is.
struct Entry {
  zip_uint64_t index = 0;
  std::string path;  // normalised: no empty or "." parts, no trailing '/'
  bool folder = false;
  std::uint64_t bytes = 0;
};

[[noreturn]] void refuse(const fs::path& archive, const std::string& why) {
  throw FmuError(archive.string() + ": " + why);
}

// The entry's name as a relative path inside the folder, or a refusal.
std::string normalised_name(const fs::path& archive, const std::string& name,
                            const ArchiveLimits& limits) {
  const std::string quoted = "entry '" + name + "'";
  if (name.size() > limits.max_name_bytes)
    refuse(archive,
           "an entry's name is longer than " + std::to_string(limits.max_name_bytes) + " bytes");
  if (name.empty() || name.find('\0') != std::string::npos) refuse(archive, "an entry has no name");
  if (name.front() == '/')
    refuse(archive, quoted + " has an absolute name (it would be written outside the folder)");
  if (name.find('\\') != std::string::npos)
    refuse(archive, quoted +
                        " has a backslash in its name (refused: it may climb out on "
                        "another system)");
  std::string out;
  std::size_t start = 0;
  while (start <= name.size()) {
    std::size_t end = name.find('/', start);
    if (end == std::string::npos) end = name.size();
    const std::string part = name.substr(start, end - start);
    if (part == "..") refuse(archive, quoted + " climbs out of the folder ('..' in its name)");
    if (!part.empty() && part != ".") out += (out.empty() ? "" : "/") + part;
    start = end + 1;
  }
  if (out.empty()) refuse(archive, quoted + " names the folder itself");
  return out;
}

// Refuses links, devices and pipes: only files and folders are unpacked.
void check_kind(const fs::path& archive, zip_t* z, zip_uint64_t i, const std::string& name) {
  zip_uint8_t system = 0;
  zip_uint32_t attributes = 0;
  if (zip_file_get_external_attributes(z, i, 0, &system, &attributes) != 0) return;
  if (system != ZIP_OPSYS_UNIX) return;
  const mode_t mode = static_cast<mode_t>(attributes >> 16);
  const mode_t kind = mode & S_IFMT;
  if (kind == S_IFLNK) refuse(archive, "entry '" + name + "' is a symbolic link (refused)");
  if (kind != 0 && kind != S_IFREG && kind != S_IFDIR)
    refuse(archive, "entry '" + name + "' is neither a file nor a folder (refused)");
}

// Every entry checked against the limits and each other, before anything
// is written.
std::vector<Entry> checked_entries(const fs::path& archive, zip_t* z, const ArchiveLimits& limits) {
  const zip_int64_t count = zip_get_num_entries(z, 0);
  if (count < 0 || static_cast<std::uint64_t>(count) > limits.max_entries)
    refuse(archive, "it has " + std::to_string(count) + " entries, more than the " +
                        std::to_string(limits.max_entries) + " an FMU may have");
  std::vector<Entry> entries;
  entries.reserve(static_cast<std::size_t>(count));
  std::map<std::string, bool> kinds;  // path -> folder
  std::uint64_t total = 0;
  for (zip_uint64_t i = 0; i < static_cast<zip_uint64_t>(count); ++i) {
    zip_stat_t st;
    zip_stat_init(&st);
    if (zip_stat_index(z, i, 0, &st) != 0 || !(st.valid & ZIP_STAT_NAME) ||
        !(st.valid & ZIP_STAT_SIZE))
      refuse(archive, "entry " + std::to_string(i) + " cannot be read: " + zip_strerror(z));
    const std::string name = st.name;
    Entry e{i, normalised_name(archive, name, limits), name.back() == '/', st.size};
    check_kind(archive, z, i, name);
    if (e.bytes > limits.max_entry_bytes)
      refuse(archive, "entry '" + name + "' unpacks to " + std::to_string(e.bytes) +
                          " bytes, more than the " + std::to_string(limits.max_entry_bytes) +
                          " allowed for one entry");
    total += e.bytes;
    if (total > limits.max_total_bytes)
      refuse(archive, "its entries unpack to more than the " +
                          std::to_string(limits.max_total_bytes) + " bytes allowed in all");
    auto [it, fresh] = kinds.emplace(e.path, e.folder);
    if (!fresh && !(e.folder && it->second))
      refuse(archive, "entry '" + name + "' lands on '" + e.path + "', as another entry does");
    entries.push_back(std::move(e));
  }
  // A file may not also be a folder of another entry ("a" and "a/b").
  for (const auto& [path, folder] : kinds) {
    for (std::size_t slash = path.find('/'); slash != std::string::npos;
         slash = path.find('/', slash + 1)) {
      auto parent = kinds.find(path.substr(0, slash));
      if (parent != kinds.end() && !parent->second)
        refuse(archive, "entry '" + parent->first + "' is a file and a folder of '" + path + "'");
    }
  }
  return entries;
}

void make_folders(const fs::path& root, const std::string& path) {
  fs::path at = root;
  for (const auto& part : fs::path(path)) {
    at /= part;
    if (::mkdir(at.c_str(), 0700) != 0 && errno != EEXIST)
      throw FmuError("cannot make folder " + at.string() + ": " + std::strerror(errno));
  }
}

void extract(const fs::path& archive, zip_t* z, const Entry& e, const fs::path& root) {
  const fs::path target = root / e.path;
  if (e.folder) return make_folders(root, e.path);
  if (const auto slash = e.path.rfind('/'); slash != std::string::npos)
    make_folders(root, e.path.substr(0, slash));
  std::unique_ptr<zip_file_t, ZipFileCloser> in(zip_fopen_index(z, e.index, 0));
  if (!in) refuse(archive, "entry '" + e.path + "' cannot be opened: " + zip_strerror(z));
  const int fd = ::open(target.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
  if (fd < 0) throw FmuError("cannot write " + target.string() + ": " + std::strerror(errno));
  std::vector<char> buf(1 << 16);
  std::uint64_t written = 0;
  for (;;) {
    const zip_int64_t n = zip_fread(in.get(), buf.data(), buf.size());
    if (n < 0) {
      ::close(fd);
      refuse(archive, "entry '" + e.path + "' cannot be read: " + zip_file_strerror(in.get()));
    }
    if (n == 0) break;
    written += static_cast<std::uint64_t>(n);
    if (written > e.bytes || ::write(fd, buf.data(), static_cast<std::size_t>(n)) != n) {
      ::close(fd);
      refuse(archive, "entry '" + e.path + "' unpacks to more than the " + std::to_string(e.bytes) +
                          " bytes it declares, or cannot be written");
    }
  }
  ::close(fd);
}

}  // namespace

UnpackedArchive::UnpackedArchive(const fs::path& archive, const ArchiveLimits& limits)
    : archive_(archive) {
  std::error_code ec;
  const auto bytes = fs::file_size(archive, ec);
  if (ec) refuse(archive, "cannot be read: " + ec.message());
  if (bytes > limits.max_archive_bytes)
    refuse(archive, "it has " + std::to_string(bytes) + " bytes, more than the " +
                        std::to_string(limits.max_archive_bytes) + " an FMU may have");
  int error = 0;
  std::unique_ptr<zip_t, ZipCloser> z(zip_open(archive.c_str(), ZIP_RDONLY, &error));
  // (No ZIP_CHECKCONS: its stricter checks refuse sound archives that other
  // tools write, cmake -E tar among them; the checks that matter are ours.)
  if (!z && error == ZIP_ER_EXISTS)  // libzip finds a name twice as it reads the directory
    refuse(archive, "two of its entries have the same name (refused)");
  if (!z) {
    zip_error_t ze;
    zip_error_init_with_code(&ze, error);
    const std::string why = zip_error_strerror(&ze);
    zip_error_fini(&ze);
    refuse(archive, "is not a zip archive an FMU can be (" + why + ")");
  }
  const std::vector<Entry> entries = checked_entries(archive, z.get(), limits);
  std::string pattern = (fs::temp_directory_path() / "railcosim-fmu-XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr)
    throw FmuError("cannot make a temporary folder to unpack " + archive.string() + ": " +
                   std::strerror(errno));
  root_ = pattern;
  try {
    for (const Entry& e : entries) extract(archive, z.get(), e, root_);
  } catch (...) {
    fs::remove_all(root_, ec);
    throw;
  }
}

UnpackedArchive::~UnpackedArchive() {
  if (root_.empty()) return;
  std::error_code ec;
  fs::remove_all(root_, ec);
}

UnpackedArchive::UnpackedArchive(UnpackedArchive&& other) noexcept
    : archive_(std::move(other.archive_)), root_(std::move(other.root_)) {
  other.root_.clear();
}

}  // namespace railcosim::fmu
