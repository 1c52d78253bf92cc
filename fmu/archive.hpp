// Unpacking a .fmu (a zip archive) into a private folder of its own. The
// archive is hostile input: every entry is checked before anything is
// written, and an archive is refused whole when any entry climbs out of the
// folder (a `..` part, an absolute name, a backslash), is a link or another
// special file, has a name another entry also lands on, or when the entries'
// count or their uncompressed sizes exceed the limits below.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

namespace railcosim::fmu {

// The bounds an archive is checked against before anything is extracted
// (the defaults are generous for real FMUs: a few hundred files, binaries of
// tens of MiB).
struct ArchiveLimits {
  std::uint64_t max_archive_bytes = std::uint64_t{1} << 30;  // the .fmu file itself: 1 GiB
  std::size_t max_entries = 10000;                           // files and folders
  std::uint64_t max_entry_bytes = std::uint64_t{256} << 20;  // one entry, uncompressed: 256 MiB
  std::uint64_t max_total_bytes = std::uint64_t{1} << 30;    // all entries, uncompressed: 1 GiB
  std::size_t max_name_bytes = 1024;                         // an entry's name
};

// An archive unpacked into a fresh folder made by mkdtemp (mode 0700) under
// the temporary directory; the folder and everything in it are removed when
// the object goes. Throws FmuError naming the file and the entry refused.
class UnpackedArchive {
 public:
  explicit UnpackedArchive(const std::filesystem::path& archive, const ArchiveLimits& limits = {});
  ~UnpackedArchive();
  UnpackedArchive(const UnpackedArchive&) = delete;
  UnpackedArchive& operator=(const UnpackedArchive&) = delete;
  UnpackedArchive(UnpackedArchive&& other) noexcept;
  UnpackedArchive& operator=(UnpackedArchive&&) = delete;

  // The folder the entries were written into.
  const std::filesystem::path& root() const { return root_; }
  // The archive it came from.
  const std::filesystem::path& archive() const { return archive_; }

 private:
  std::filesystem::path archive_;
  std::filesystem::path root_;
};

}  // namespace railcosim::fmu
