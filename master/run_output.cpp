#include "run_output.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <stdexcept>

namespace railcosim {
namespace {

// Shortest text that reads back to the same double.
std::string num(double v) {
  char buf[32];
  for (int prec = 15; prec <= 17; ++prec) {
    std::snprintf(buf, sizeof buf, "%.*g", prec, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string json_opt(const std::optional<std::string>& s) {
  return s ? json_string(*s) : "null";
}
std::string json_opt(const std::optional<double>& v) {
  return v && std::isfinite(*v) ? num(*v) : "null";
}

// Why the last C library call failed, e.g. "No space left on device".
std::string reason() {
  return std::strerror(errno);
}

// Writes all of `text` to an open file and closes it; false (errno set) if
// any byte could not be written.
bool write_and_close(std::FILE* f, const std::string& text) {
  const bool wrote = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  const bool flushed = wrote && std::fflush(f) == 0;
  const int saved = errno;
  const bool closed = std::fclose(f) == 0;
  if (!flushed) errno = saved;
  return flushed && closed;
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path, const std::string& text) {
  const std::filesystem::path tmp = path.string() + ".part";
  std::FILE* f = std::fopen(tmp.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + path.string() + ": " + reason());
  if (!write_and_close(f, text)) {
    const std::string why = reason();
    std::error_code ec;
    std::filesystem::remove(tmp, ec);  // no stray half file
    throw std::runtime_error("cannot write " + path.string() + ": " + why);
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error("cannot write " + path.string() + ": " + ec.message());
  }
}

std::string format_double(double v) {
  return std::isfinite(v) ? num(v) : "null";
}

std::string summary_json(const RunRecord& r) {
  std::ostringstream s;
  s << "{\n";
  s << "  \"case\": " << json_string(r.case_name) << ",\n";
  s << "  \"split\": " << json_opt(r.split) << ",\n";
  s << "  \"coupling\": " << json_opt(r.coupling) << ",\n";
  s << "  \"scheme\": " << json_opt(r.scheme) << ",\n";
  s << "  \"feedthrough\": " << json_opt(r.feedthrough) << ",\n";
  s << "  \"macro_step_s\": " << num(r.macro_step) << ",\n";
  s << "  \"t_end_s\": " << num(r.t_end) << ",\n";
  s << "  \"wall_s\": " << num(r.wall_s) << ",\n";
  s << "  \"macro_steps\": " << r.macro_steps << ",\n";
  s << "  \"micro_steps\": {";
  bool first = true;
  for (const auto& [k, v] : r.micro_steps) {
    s << (first ? "" : ", ") << json_string(k) << ": " << v;
    first = false;
  }
  s << "},\n";
  s << "  \"status\": " << json_string(r.status) << ",\n";
  s << "  \"message\": " << json_string(r.message) << ",\n";
  s << "  \"max_abs_error_m\": " << json_opt(r.max_abs_error_m) << ",\n";
  s << "  \"rel_l2_error\": " << json_opt(r.rel_l2_error) << ",\n";
  s << "  \"history_error\": " << json_opt(r.history_error) << ",\n";
  s << "  \"transport\": " << json_string(r.transport) << ",\n";
  s << "  \"restart\": " << json_string(r.restart) << "\n";
  s << "}\n";
  return s.str();
}

namespace {

std::string deflection_csv(const RunRecord& r) {
  std::string text = "x_m,w_m\n";
  for (std::size_t k = 0; k < r.deflection.size() && k < r.x.size(); ++k)
    text += num(r.x[k]) + "," + num(r.deflection[k]) + "\n";
  return text;
}

std::string history_line(const HistoryRow& h) {
  std::string line = num(h.t) + "," + num(h.wheel) + "," + num(h.contact_force);
  for (double v : h.extra) {
    line += ',';
    line += num(v);
  }
  line += '\n';
  return line;
}

// The fixed columns, then the further channels the participants declared.
std::string history_header(const std::vector<std::string>& extra) {
  std::string h = "t_s,wheel_m,contact_force_N";
  for (const auto& name : extra) {
    h += ',';
    h += name;
  }
  h += '\n';
  return h;
}

std::string soil_csv(const RunRecord& r) {
  std::string text = "x_m,s_m\n";
  for (std::size_t i = 0; i < r.soil.size() && i < r.soil_x.size(); ++i)
    text += num(r.soil_x[i]) + "," + num(r.soil[i]) + "\n";
  return text;
}

std::filesystem::path make_run_dir(const std::filesystem::path& out_dir, const std::string& name) {
  const std::filesystem::path dir = out_dir / name;
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create " + dir.string() + ": " + ec.message());
  return dir;
}

}  // namespace

std::filesystem::path write_run(const std::filesystem::path& out_dir, const RunRecord& r) {
  const std::filesystem::path dir = make_run_dir(out_dir, r.case_name);
  write_file_atomically(dir / "deflection.csv", deflection_csv(r));
  std::string text = history_header(r.extra_channels);
  for (const auto& h : r.history) text += history_line(h);
  write_file_atomically(dir / "history.csv", text);
  if (!r.soil.empty()) write_file_atomically(dir / "soil.csv", soil_csv(r));
  write_file_atomically(dir / "summary.json", summary_json(r));
  return dir;
}

RunWriter::RunWriter(const std::filesystem::path& out_dir, const std::string& folder)
    : dir_(make_run_dir(out_dir, folder)) {
  // A summary from an earlier run in this folder must not pass for this one.
  std::error_code ec;
  std::filesystem::remove(dir_ / "summary.json", ec);
  std::filesystem::remove(dir_ / "deflection.csv", ec);
  std::filesystem::remove(dir_ / "soil.csv", ec);
  // Room for the summary, taken before the history can fill the disk: the
  // summary overwrites this placeholder, so a run that fails on a full disk
  // still says why.
  const std::filesystem::path reserve = dir_ / "summary.json.part";
  std::FILE* r = std::fopen(reserve.c_str(), "w");
  if (!r || !write_and_close(r, std::string(kSummaryReserve, ' '))) {
    const std::string why = reason();
    std::filesystem::remove(reserve, ec);
    throw std::runtime_error("cannot write " + (dir_ / "summary.json").string() + ": " + why);
  }
  history_ = std::fopen((dir_ / "history.csv").c_str(), "w");
  if (!history_)
    throw std::runtime_error("cannot write " + (dir_ / "history.csv").string() + ": " + reason());
}

void RunWriter::channels(const std::vector<std::string>& extra) {
  extra_ = extra;
}

void RunWriter::put(const std::string& text) {
  if (!history_) return;
  if (std::fputs(text.c_str(), history_) < 0 || std::fflush(history_) != 0) {
    const std::string why = reason();
    std::fclose(history_);
    history_ = nullptr;
    std::error_code ec;
    if (!wrote_history_) std::filesystem::remove(dir_ / "history.csv", ec);  // not even a header
    throw std::runtime_error("cannot write " + (dir_ / "history.csv").string() + ": " + why);
  }
  wrote_history_ = true;
}

void RunWriter::header() {
  if (header_written_ || !history_) return;
  header_written_ = true;
  put(history_header(extra_));
}

RunWriter::~RunWriter() {
  if (history_) std::fclose(history_);
  std::error_code ec;
  std::filesystem::remove(dir_ / "summary.json.part", ec);  // unused reserve
}

void RunWriter::row(const HistoryRow& row) {
  header();
  put(history_line(row));
}

void RunWriter::finish(const RunRecord& run) {
  RunRecord r = run;
  // Every file that can be written is; the first that cannot fails the run,
  // and the summary (written last, into its reserved room) says why.
  std::string error;
  auto attempt = [&](auto&& write) {
    try {
      write();
    } catch (const std::exception& e) {
      if (error.empty()) error = e.what();
    }
  };
  attempt([&] {
    header();
    if (history_ && std::fclose(history_) != 0) {
      history_ = nullptr;
      throw std::runtime_error("cannot write " + (dir_ / "history.csv").string() + ": " + reason());
    }
    history_ = nullptr;
  });
  if (!r.deflection.empty())
    attempt([&] { write_file_atomically(dir_ / "deflection.csv", deflection_csv(r)); });
  if (!r.soil.empty()) attempt([&] { write_file_atomically(dir_ / "soil.csv", soil_csv(r)); });
  if (!error.empty() && r.status != "failed") {
    r.status = "failed";
    r.message = error;
  }
  write_file_atomically(dir_ / "summary.json", summary_json(r));
  if (!error.empty()) throw std::runtime_error(error);
}

}  // namespace railcosim
