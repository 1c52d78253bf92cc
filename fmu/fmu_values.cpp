// Fmu's reading of one value of any type the host reads (fmu.hpp).
#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "fmi_api.hpp"
#include "fmu.hpp"
#include "fmu_api_table.hpp"
#include "fmu_error.hpp"

namespace railcosim::fmu {

namespace {

// The most values one array variable may hold, checked before any is read.
constexpr std::uint64_t kMaxArrayValues = 10'000'000;

std::string base_type(const std::string& type) {
  const std::string suffix = " array";
  return type.size() > suffix.size() &&
                 type.compare(type.size() - suffix.size(), suffix.size(), suffix) == 0
             ? type.substr(0, type.size() - suffix.size())
             : type;
}

}  // namespace

bool Fmu::readable(FmiVersion version, const std::string& type) {
  const std::string t = base_type(type);
  if (t == "Real" || t == "Float64" || t == "Boolean") return true;
  if (version == FmiVersion::k2) return t == "Integer" || t == "Enumeration";
  for (const char* x : {"Float32", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64",
                        "UInt64", "Enumeration"})
    if (t == x) return true;
  return false;
}

double Fmu::get_value(const Variable& v) {
  const std::vector<double> values = get_values(v);
  if (values.size() != 1)
    throw FmuError("FMU " + name_ + ": " + v.name + " holds " + std::to_string(values.size()) +
                   " values, not one");
  return values[0];
}

std::size_t Fmu::array_size(const Variable& v) {
  std::uint64_t n = 1;
  for (const Variable::Dimension& d : v.dimensions) {
    std::uint64_t size = d.start.value_or(0);
    if (!d.start) {
      const Variable* p = nullptr;
      for (const Variable& w : description_.variables)
        if (w.value_reference == *d.value_reference && w.dimensions.empty()) p = &w;
      if (p == nullptr)
        throw FmuError("FMU " + name_ + ": the dimension of " + v.name + " names value reference " +
                       std::to_string(*d.value_reference) + ", which no scalar variable has");
      const double got = get_value(*p);
      if (!(got >= 0) || got > static_cast<double>(kMaxArrayValues))
        throw FmuError("FMU " + name_ + ": the dimension of " + v.name + " (" + p->name +
                       ") is out of bounds");
      size = static_cast<std::uint64_t>(got);
    }
    if (size != 0 && n > kMaxArrayValues / size)
      throw FmuError("FMU " + name_ + ": " + v.name + " holds more than " +
                     std::to_string(kMaxArrayValues) + " values");
    n *= size;
  }
  return static_cast<std::size_t>(n);
}

std::vector<double> Fmu::get_values(const Variable& v) {
  need_instance("get_values");
  const std::size_t n = array_size(v);
  const std::string type = base_type(v.type);
  auto call = [&](auto fn, const char* symbol, auto zero) -> std::vector<double> {
    if (fn == nullptr)
      throw FmuError("FMU " + name_ + ": its binary does not export " + symbol + ", to read " +
                     v.name);
    const std::uint32_t vr = v.value_reference;
    // Not std::vector: its bool specialisation holds no array of bool.
    const auto raw = std::make_unique<decltype(zero)[]>(std::max<std::size_t>(n, 1));
    if constexpr (std::is_invocable_v<decltype(fn), void*, const std::uint32_t*, std::size_t,
                                      decltype(raw.get()), std::size_t>)
      check(fn(instance_, &vr, 1, raw.get(), n), symbol);
    else
      check(fn(instance_, &vr, 1, raw.get()), symbol);
    return std::vector<double>(raw.get(), raw.get() + n);
  };
  const bool v2 = version() == FmiVersion::k2;
  if (v2 && type == "Real") return call(api_->v2.get_real, "fmi2GetReal", 0.0);
  if (v2 && (type == "Integer" || type == "Enumeration"))
    return call(api_->v2.get_integer, "fmi2GetInteger", fmi2::Integer{});
  if (v2 && type == "Boolean") return call(api_->v2.get_boolean, "fmi2GetBoolean", fmi2::Boolean{});
  if (!v2 && type == "Float64") return call(api_->v3.get_float64, "fmi3GetFloat64", 0.0);
  if (!v2 && type == "Float32") return call(api_->v3.get_float32, "fmi3GetFloat32", 0.0F);
  if (!v2 && type == "Int32") return call(api_->v3.get_int32, "fmi3GetInt32", std::int32_t{});
  if (!v2 && type == "Int8") return call(api_->v3.get_int8, "fmi3GetInt8", std::int8_t{});
  if (!v2 && type == "UInt8") return call(api_->v3.get_uint8, "fmi3GetUInt8", std::uint8_t{});
  if (!v2 && type == "Int16") return call(api_->v3.get_int16, "fmi3GetInt16", std::int16_t{});
  if (!v2 && type == "UInt16") return call(api_->v3.get_uint16, "fmi3GetUInt16", std::uint16_t{});
  if (!v2 && type == "UInt32") return call(api_->v3.get_uint32, "fmi3GetUInt32", std::uint32_t{});
  if (!v2 && type == "UInt64") return call(api_->v3.get_uint64, "fmi3GetUInt64", std::uint64_t{});
  if (!v2 && (type == "Int64" || type == "Enumeration"))
    return call(api_->v3.get_int64, "fmi3GetInt64", std::int64_t{});
  if (!v2 && type == "Boolean") return call(api_->v3.get_boolean, "fmi3GetBoolean", false);
  throw FmuError("FMU " + name_ + ": " + v.name + " is of type " + v.type +
                 ", which the host cannot read");
}

}  // namespace railcosim::fmu
