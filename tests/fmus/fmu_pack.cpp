// Build-time tool: packs a test FMU (a .fmu zip archive) from its
// description and binary.
// Usage: fmu_pack OUT.fmu modelDescription.xml PLATFORM BINARY.so
// writes modelDescription.xml and binaries/PLATFORM/<BINARY's file name>.
#include <zip.h>

#include <cstdio>
#include <filesystem>
#include <string>

namespace {

bool add(zip_t* z, const std::string& name, const char* file) {
  zip_source_t* src = zip_source_file(z, file, 0, -1);
  if (src == nullptr || zip_file_add(z, name.c_str(), src, ZIP_FL_ENC_UTF_8) < 0) {
    std::fprintf(stderr, "fmu_pack: cannot add %s: %s\n", file, zip_strerror(z));
    if (src != nullptr) zip_source_free(src);
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: fmu_pack OUT.fmu modelDescription.xml PLATFORM BINARY.so\n");
    return 2;
  }
  int error = 0;
  zip_t* z = zip_open(argv[1], ZIP_CREATE | ZIP_TRUNCATE, &error);
  if (z == nullptr) {
    std::fprintf(stderr, "fmu_pack: cannot create %s (libzip error %d)\n", argv[1], error);
    return 1;
  }
  const std::string binary =
      std::string("binaries/") + argv[3] + "/" + std::filesystem::path(argv[4]).filename().string();
  if (!add(z, "modelDescription.xml", argv[2]) || !add(z, binary, argv[4])) {
    zip_discard(z);
    return 1;
  }
  if (zip_close(z) != 0) {
    std::fprintf(stderr, "fmu_pack: cannot write %s: %s\n", argv[1], zip_strerror(z));
    zip_discard(z);
    return 1;
  }
  return 0;
}
