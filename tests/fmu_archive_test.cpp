// Unpacking a .fmu as hostile input (fmu/archive): each refusal on an
// archive this test writes itself with libzip, and nothing written to disk
// before an archive is refused.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <zip.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "archive.hpp"
#include "fmu_error.hpp"

namespace fmu_archive_test {
namespace fs = std::filesystem;
using railcosim::fmu::ArchiveLimits;
using railcosim::fmu::FmuError;
using railcosim::fmu::UnpackedArchive;

struct Item {
  std::string name;
  std::string content;
  bool symlink = false;
};

class FmuArchive : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string dir = (fs::temp_directory_path() / "fmu-archive-test-XXXXXX").string();
    ASSERT_NE(::mkdtemp(dir.data()), nullptr);
    dir_ = dir;
    fs::create_directory(dir_ / "tmp");
    // Unpacked folders go here, so the test sees whatever is written.
    ::setenv("TMPDIR", (dir_ / "tmp").c_str(), 1);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes a zip of `items` (names as given, in order) and returns its path.
  fs::path zip(const std::vector<Item>& items, const std::string& file = "test.fmu") {
    const fs::path path = dir_ / file;
    int error = 0;
    zip_t* z = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &error);
    EXPECT_NE(z, nullptr);
    for (const Item& i : items) {
      zip_source_t* src = zip_source_buffer(z, i.content.data(), i.content.size(), 0);
      const zip_int64_t at = i.name.back() == '/' ? zip_dir_add(z, i.name.c_str(), 0)
                                                  : zip_file_add(z, i.name.c_str(), src, 0);
      EXPECT_GE(at, 0) << i.name << ": " << zip_strerror(z);
      if (i.name.back() == '/') zip_source_free(src);
      if (i.symlink)
        zip_file_set_external_attributes(z, static_cast<zip_uint64_t>(at), 0, ZIP_OPSYS_UNIX,
                                         static_cast<zip_uint32_t>(S_IFLNK | 0777) << 16);
    }
    EXPECT_EQ(zip_close(z), 0);
    return path;
  }

  // The message of the refusal of `archive`, with nothing left on disk.
  std::string refusal(const fs::path& archive, const ArchiveLimits& limits = {}) {
    try {
      UnpackedArchive a(archive, limits);
    } catch (const FmuError& e) {
      EXPECT_TRUE(fs::is_empty(dir_ / "tmp")) << "something was unpacked before the refusal";
      return e.what();
    }
    ADD_FAILURE() << archive << " was not refused";
    return "";
  }

  fs::path dir_;
};

TEST_F(FmuArchive, UnpacksFilesAndFoldersIntoAPrivateFolderRemovedAfterUse) {
  const fs::path a = zip({{"modelDescription.xml", "<x/>"},
                          {"binaries/", ""},
                          {"binaries/linux64/m.so", std::string(3000, 'b')},
                          {"./resources/data.txt", "abc"}});
  fs::path root;
  {
    UnpackedArchive u(a);
    root = u.root();
    EXPECT_EQ(root.parent_path(), dir_ / "tmp");
    EXPECT_EQ(fs::status(root).permissions() & fs::perms::all, fs::perms::owner_all);
    std::ifstream in(root / "binaries/linux64/m.so");
    std::stringstream s;
    s << in.rdbuf();
    EXPECT_EQ(s.str(), std::string(3000, 'b'));
    EXPECT_TRUE(fs::is_regular_file(root / "resources/data.txt"));
    EXPECT_TRUE(fs::is_regular_file(root / "modelDescription.xml"));
  }
  EXPECT_FALSE(fs::exists(root));
}

TEST_F(FmuArchive, RefusesEntriesThatClimbOut) {
  EXPECT_NE(refusal(zip({{"ok.txt", "1"}, {"../evil.txt", "x"}}))
                .find("entry '../evil.txt' climbs out of the folder"),
            std::string::npos);
  EXPECT_NE(refusal(zip({{"a/../../evil.txt", "x"}})).find("climbs out"), std::string::npos);
  EXPECT_NE(refusal(zip({{"/etc/evil.txt", "x"}})).find("has an absolute name"), std::string::npos);
  EXPECT_NE(refusal(zip({{"..\\evil.txt", "x"}})).find("backslash"), std::string::npos);
}

TEST_F(FmuArchive, RefusesSymbolicLinks) {
  const std::string m = refusal(zip({{"ok.txt", "1"}, {"binaries/link", "/etc/passwd", true}}));
  EXPECT_NE(m.find("test.fmu: entry 'binaries/link' is a symbolic link"), std::string::npos) << m;
}

TEST_F(FmuArchive, RefusesTooManyEntriesBeforeReadingThem) {
  ArchiveLimits limits;
  limits.max_entries = 3;
  const std::string m = refusal(zip({{"a", "1"}, {"b", "2"}, {"c", "3"}, {"d", "4"}}), limits);
  EXPECT_NE(m.find("it has 4 entries, more than the 3 an FMU may have"), std::string::npos) << m;
  EXPECT_NO_THROW(UnpackedArchive(zip({{"a", "1"}, {"b", "2"}, {"c", "3"}}, "three.fmu"), limits));
}

TEST_F(FmuArchive, RefusesEntriesLargerThanTheBoundsUnpacked) {
  ArchiveLimits limits;
  limits.max_entry_bytes = 1000;
  limits.max_total_bytes = 1500;
  // Zeros compress to a few bytes: the bound is on the declared unpacked size.
  std::string m = refusal(zip({{"small", "1"}, {"bomb", std::string(1001, '\0')}}), limits);
  EXPECT_NE(m.find("entry 'bomb' unpacks to 1001 bytes, more than the 1000 allowed for one entry"),
            std::string::npos)
      << m;
  m = refusal(zip({{"a", std::string(800, '\0')}, {"b", std::string(800, '\0')}}), limits);
  EXPECT_NE(m.find("its entries unpack to more than the 1500 bytes allowed in all"),
            std::string::npos)
      << m;
  EXPECT_NO_THROW(UnpackedArchive(zip({{"a", std::string(1000, '\0')}}, "ok.fmu"), limits));
}

TEST_F(FmuArchive, RefusesTwoEntriesThatLandOnOneFile) {
  // Two names for one path.
  std::string m = refusal(zip({{"a/b.txt", "1"}, {"a/./b.txt", "2"}}));
  EXPECT_NE(m.find("entry 'a/./b.txt' lands on 'a/b.txt', as another entry does"),
            std::string::npos)
      << m;
  // The same name twice (libzip will not write it, so the bytes are edited).
  const fs::path a = zip({{"aaaa.txt", "1"}, {"bbbb.txt", "2"}});
  std::string bytes;
  {
    std::ifstream in(a, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    bytes = s.str();
  }
  for (auto at = bytes.find("bbbb.txt"); at != std::string::npos; at = bytes.find("bbbb.txt"))
    bytes.replace(at, 8, "aaaa.txt");
  std::ofstream(a, std::ios::binary | std::ios::trunc) << bytes;
  m = refusal(a);
  EXPECT_NE(m.find("test.fmu: entry 'aaaa.txt' lands on 'aaaa.txt', as another entry does"),
            std::string::npos)
      << m;
  // A file that is also another entry's folder.
  m = refusal(zip({{"a", "1"}, {"a/b", "2"}}));
  EXPECT_NE(m.find("entry 'a' is a file and a folder of 'a/b'"), std::string::npos) << m;
}

TEST_F(FmuArchive, RefusesWhatIsNotAZipArchive) {
  std::ofstream(dir_ / "text.fmu") << "not a zip archive";
  const std::string m = refusal(dir_ / "text.fmu");
  EXPECT_NE(m.find("text.fmu: is not a zip archive an FMU can be"), std::string::npos) << m;
  ArchiveLimits limits;
  limits.max_archive_bytes = 10;
  EXPECT_NE(refusal(dir_ / "text.fmu", limits).find("more than the 10 an FMU may have"),
            std::string::npos);
}

}  // namespace fmu_archive_test
