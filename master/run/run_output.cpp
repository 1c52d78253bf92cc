#include "run/run_output.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include "spectra.hpp"

namespace railcosim::run {
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
// {"key": value, ...} in key order (counts print as integers: below 2^53).
template <class T>
std::string json_object(const std::map<std::string, T>& m) {
  std::string s;
  for (const auto& [k, v] : m)
    s += (s.empty() ? "" : ", ") + json_string(k) + ": " + num(static_cast<double>(v));
  return "{" + s + "}";
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
std::string json_quoted(const std::string& text) {
  return json_string(text);
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
  s << "  \"history_rows\": " << r.history_rows.value_or(static_cast<long>(r.history.size()))
    << ",\n";
  s << "  \"micro_steps\": " << json_object(r.micro_steps) << ",\n";
  s << "  \"windows\": " << json_object(r.windows) << ",\n";
  s << "  \"status\": " << json_string(r.status) << ",\n";
  s << "  \"message\": " << json_string(r.message) << ",\n";
  s << "  \"max_abs_error_m\": " << json_opt(r.max_abs_error_m) << ",\n";
  s << "  \"rel_l2_error\": " << json_opt(r.rel_l2_error) << ",\n";
  s << "  \"history_error\": " << json_opt(r.history_error) << ",\n";
  s << judgement_json(r);
  s << "  \"transport\": " << json_string(r.transport) << ",\n";
  if (!r.data_plane.empty()) s << "  \"data_plane\": " << json_string(r.data_plane) << ",\n";
  if (!r.data_plane_mode.empty()) s << "  \"data_plane_mode\": \"" << r.data_plane_mode << "\",\n";
  s << "  \"restart\": " << json_string(r.restart) << ",\n";
  s << "  \"method\": " << json_string(r.method) << ",\n";
  s << "  \"inputs\": " << json_string(r.inputs) << ",\n";
  s << "  \"accelerator\": " << json_opt(r.accelerator) << ",\n";
  s << "  \"iterations\": ";
  if (r.iterations_mean)
    s << "{\"mean\": " << num(*r.iterations_mean) << ", \"max\": " << *r.iterations_max
      << ", \"not_converged_steps\": " << *r.not_converged_steps << "}\n";
  else
    s << "null\n";
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

bool is_ballast(const std::string& channel) {
  return channel.rfind("ballast_force_", 0) == 0;
}

std::vector<bool> history_mask(const std::vector<std::string>& extra) {
  std::vector<bool> m;
  for (const auto& name : extra) m.push_back(!is_ballast(name));
  return m;
}

std::string history_line(const HistoryRow& h, const std::vector<bool>& mask) {
  std::string line = num(h.t) + "," + num(h.wheel) + "," + num(h.contact_force);
  for (std::size_t k = 0; k < h.extra.size(); ++k) {
    if (k < mask.size() && !mask[k]) continue;
    line += ',';
    line += num(h.extra[k]);
  }
  line += '\n';
  return line;
}

// The fixed columns, then the further channels the participants declared
// (the ballast forces go to soil_forces.csv).
std::string history_header(const std::vector<std::string>& extra) {
  std::string h = "t_s,wheel_m,contact_force_N";
  for (const auto& name : extra) {
    if (is_ballast(name)) continue;
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

// Implicit runs: one row per iteration, the relative residual per quantity.
std::string convergence_csv(const RunRecord& r) {
  std::string text = "step,iteration";
  for (const auto& q : r.convergence_quantities) {
    text += ',';
    text += q;
  }
  text += '\n';
  for (const auto& row : r.convergence) {
    text += std::to_string(row.step);
    text += ',';
    text += std::to_string(row.iteration);
    for (double v : row.residual) {
      text += ',';
      text += num(v);
    }
    text += '\n';
  }
  return text;
}

}  // namespace

std::string soil_forces_csv(const RunRecord& r) {
  std::vector<std::size_t> cols;
  for (std::size_t k = 0; k < r.extra_channels.size(); ++k)
    if (is_ballast(r.extra_channels[k])) cols.push_back(k);
  if (cols.empty()) return "";
  std::string text = "t_s";
  for (std::size_t i = 0; i < cols.size(); ++i) {
    text += ',';
    text += i < r.sleeper_x.size() ? num(r.sleeper_x[i]) : r.extra_channels[cols[i]];
  }
  text += '\n';
  for (const HistoryRow& h : r.history) {
    text += num(h.t);
    for (std::size_t k : cols) {
      text += ',';
      text += k < h.extra.size() ? num(h.extra[k]) : "";
    }
    text += '\n';
  }
  return text;
}

std::string spectra_csv(const RunRecord& r) {
  if (r.history.size() < 16) return "";
  const double dt = r.history[1].t - r.history[0].t;
  const double span = r.history.back().t - r.history.front().t;
  if (!(dt > 0) || !(span > 0)) return "";
  std::vector<std::pair<std::string, std::vector<double>>> signals;
  std::vector<double> total;
  for (const HistoryRow& h : r.history) total.push_back(h.contact_force);
  signals.emplace_back("contact_force_N", std::move(total));
  for (std::size_t k = 0; k < r.extra_channels.size(); ++k) {
    const std::string& name = r.extra_channels[k];
    if (!is_ballast(name) && name.rfind("force_w", 0) != 0) continue;
    std::vector<double> x;
    for (const HistoryRow& h : r.history) x.push_back(k < h.extra.size() ? h.extra[k] : 0.0);
    signals.emplace_back(name, std::move(x));
  }
  std::string text = "signal,band,centre_Hz,lower_Hz,upper_Hz,rms,level_dB\n";
  const double f_min = 2.0 / span, f_max = 0.5 / dt;
  for (const auto& [name, x] : signals) {
    for (const Band& b : third_octave_spectrum(x, dt, f_min, f_max)) {
      text += name + "," + std::to_string(b.index) + "," + num(b.centre) + "," + num(b.lower) +
              "," + num(b.upper) + "," + num(b.rms) + ",";
      text += std::isfinite(b.level_db) ? num(b.level_db) : "";
      text += '\n';
    }
  }
  return text;
}

namespace {

void write_channel_files(const std::filesystem::path& dir, const RunRecord& r) {
  if (const std::string f = soil_forces_csv(r); !f.empty())
    write_file_atomically(dir / "soil_forces.csv", f);
  if (r.status == "failed") return;
  if (const std::string s = spectra_csv(r); !s.empty())
    write_file_atomically(dir / "spectra.csv", s);
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
  const std::vector<bool> mask = history_mask(r.extra_channels);
  for (const auto& h : r.history) text += history_line(h, mask);
  write_file_atomically(dir / "history.csv", text);
  if (!r.soil.empty()) write_file_atomically(dir / "soil.csv", soil_csv(r));
  if (!r.convergence.empty()) write_file_atomically(dir / "convergence.csv", convergence_csv(r));
  write_channel_files(dir, r);
  write_file_atomically(dir / "summary.json", summary_json(r));
  return dir;
}

RunWriter::RunWriter(const std::filesystem::path& out_dir, const std::string& folder)
    : dir_(make_run_dir(out_dir, folder)) {
  // A summary from an earlier run in this folder must not pass for this one.
  std::error_code ec;
  for (const char* f : {"summary.json", "deflection.csv", "soil.csv", "convergence.csv",
                        "soil_forces.csv", "spectra.csv"})
    std::filesystem::remove(dir_ / f, ec);
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
  history_ = std::make_unique<BlockWriter>(dir_ / "history.csv");
}

long RunWriter::history_rows() const {
  return history_ ? std::max(0L, history_->lines_written() - 1) : 0;
}

void RunWriter::channels(const std::vector<std::string>& extra) {
  extra_ = extra;
  in_history_ = history_mask(extra);
}

namespace {

// Runs a write of history.csv; when it fails, a file that holds nothing
// (not even the header) is removed before the error goes on.
template <class Write>
void guard_history(BlockWriter& history, Write&& write) {
  try {
    write();
  } catch (const std::runtime_error&) {
    std::error_code ec;
    if (history.bytes_written() == 0) std::filesystem::remove(history.path(), ec);
    throw;
  }
}

}  // namespace

void RunWriter::put(const std::string& text) {
  if (history_) guard_history(*history_, [&] { history_->append(text); });
}

void RunWriter::header() {
  if (header_written_ || !history_) return;
  header_written_ = true;
  put(history_header(extra_));
}

RunWriter::~RunWriter() {
  history_.reset();  // writes the rows it still holds
  std::error_code ec;
  std::filesystem::remove(dir_ / "summary.json.part", ec);  // unused reserve
}

void RunWriter::row(const HistoryRow& row) {
  header();
  put(history_line(row, in_history_));
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
    if (history_) guard_history(*history_, [&] { history_->close(); });
  });
  r.history_rows = history_rows();
  // A run that failed on the way counts the macro steps every participant
  // completed: the rows of history.csv after the one of t = 0.
  if (r.status == "failed") r.macro_steps = std::max(0L, *r.history_rows - 1);
  if (!r.deflection.empty())
    attempt([&] { write_file_atomically(dir_ / "deflection.csv", deflection_csv(r)); });
  if (!r.soil.empty()) attempt([&] { write_file_atomically(dir_ / "soil.csv", soil_csv(r)); });
  if (!r.convergence.empty())
    attempt([&] { write_file_atomically(dir_ / "convergence.csv", convergence_csv(r)); });
  attempt([&] { write_channel_files(dir_, r); });
  if (!error.empty() && r.status != "failed") {
    r.status = "failed";
    r.message = error;
  }
  write_file_atomically(dir_ / "summary.json", summary_json(r));
  if (!error.empty()) throw std::runtime_error(error);
}

}  // namespace railcosim::run
