// ecat-esigen: one device description in, ESI / SII / C++ tables / device XML
// out (STYLE lesson 3). Either a device file in our format (or the built-in
// generic servo) or, with --from-esi, a vendor's ESI.
//
//   ecat-esigen DEVICE.xml --esi OUT.xml [--sii OUT.bin] [--cpp OUT.hpp]
//   ecat-esigen --from-esi VENDOR.xml [--product-code X] [--revision Y] [--type NAME]
//               [--device-xml OUT.xml] [--esi OUT.xml] [--sii OUT.bin] [--cpp OUT.hpp]
//   ecat-esigen --from-esi VENDOR.xml --list   (one line per device: type, product
//               code, revision, name, tab-separated; esi/esi_device_list.hpp)
//
// Every output is made in memory first, then written to a temporary name next
// to its target and renamed only when all outputs are ready, so a failed run
// leaves no file half-written. Errors: one line "file:line: message", exit 1;
// bad options: exit 2.
#include <cctype>
#include <cstdio>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "esi/atomic_file.hpp"
#include "esi/cpp_writer.hpp"
#include "esi/esi_device_list.hpp"
#include "esi/device_loader.hpp"
#include "esi/esi_reader.hpp"
#include "esi/esi_writer.hpp"
#include "esi/esi_writer_device_xml.hpp"
#include "esi/sii_writer.hpp"
#include "esi/twin_import.hpp"

namespace {

constexpr int kExitError = 1;
constexpr int kExitUsage = 2;

struct Options {
  std::string device;
  std::string from_esi;
  std::string product_code;
  std::string revision;
  std::string type_name;
  bool list = false;
  std::string esi_out;
  std::string sii_out;
  std::string cpp_out;
  std::string cpp_namespace = "ecat_device";
  std::string device_xml_out;
  bool strict = false;
};

// A C++ namespace name: identifiers joined by "::".
bool valid_namespace(const std::string& ns) {
  std::size_t start = 0;
  for (;;) {
    const std::size_t end = ns.find("::", start);
    const std::string part = ns.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (part.empty() || std::isdigit(static_cast<unsigned char>(part[0]))) return false;
    for (char c : part) {
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
    }
    if (end == std::string::npos) return true;
    start = end + 2;
  }
}

int usage_error(const std::string& message) {
  std::fprintf(stderr, "ecat-esigen: %s\n", message.c_str());
  return kExitUsage;
}

int error(const std::string& line) {
  std::fprintf(stderr, "%s\n", line.c_str());
  return kExitError;
}

int run(const Options& o) {
  using ecat::esi::LoadError;
  ecat::Expected<ecat::od::DeviceDescription, LoadError> device = ecat::fail(LoadError{});
  std::string source;
  if (!o.from_esi.empty()) {
    std::optional<std::uint32_t> pc;
    std::optional<std::uint32_t> rev;
    if (!o.product_code.empty() && !(pc = ecat::esi::parse_esi_number(o.product_code))) {
      return usage_error(fmt::format("--product-code '{}' is not a number (#x.., 0x.. or decimal)",
                                     o.product_code));
    }
    if (!o.revision.empty() && !(rev = ecat::esi::parse_esi_number(o.revision))) {
      return usage_error(fmt::format("--revision '{}' is not a number (#x.., 0x.. or decimal)",
                                     o.revision));
    }
    std::optional<std::string> type;
    if (!o.type_name.empty()) type = o.type_name;
    std::vector<ecat::esi::EsiWarning> warnings;
    device = ecat::esi::read_esi(o.from_esi, ecat::esi::EsiSelection{pc, rev, type}, &warnings);
    for (const auto& w : warnings) std::fprintf(stderr, "%s\n", w.to_string(o.from_esi).c_str());
    source = o.from_esi;
    if (device && o.strict) {
      if (auto f = ecat::esi::strict_failure(warnings, o.from_esi)) return error(f->to_string());
    }
  } else if (!o.device.empty()) {
    device = ecat::esi::load_device_file(o.device);
    source = o.device;
  } else {
    device = ecat::esi::load_default_device();
    source = "<built-in generic servo>";
  }
  if (!device) return error(device.error().to_string());

  // Everything in memory first: a failure here writes nothing.
  ecat::esi::StagedFiles files;
  auto stage = [&](const std::string& path, auto&& content) -> bool {
    if (path.empty()) return true;
    auto ok = files.stage(path, content);
    if (!ok) error(ok.error());
    return static_cast<bool>(ok);
  };
  std::vector<std::uint8_t> sii;
  if (!o.sii_out.empty()) {
    auto out = ecat::esi::write_sii_detailed(*device);
    if (!out) return error(fmt::format("{}: SII: {}", source, out.error()));
    if (out->detail != ecat::esi::SiiDetail::Full) {
      std::fprintf(stderr, "%s: warning: SII written %s: the %u-byte EEPROM cannot hold more\n",
                   source.c_str(), ecat::esi::to_string(out->detail),
                   static_cast<unsigned>(device->esc.eeprom_bytes));
    }
    sii = std::move(out->bytes);
  }
  if (!stage(o.esi_out, o.esi_out.empty() ? std::string{} : ecat::esi::write_esi(*device)) ||
      !stage(o.sii_out, std::span<const std::uint8_t>(sii)) ||
      !stage(o.cpp_out,
             o.cpp_out.empty() ? std::string{} : ecat::esi::write_cpp_tables(*device, o.cpp_namespace)) ||
      !stage(o.device_xml_out,
             o.device_xml_out.empty() ? std::string{} : ecat::esi::write_device_xml(*device))) {
    return kExitError;
  }
  if (auto ok = files.commit(); !ok) return error(ok.error());
  return 0;
}

// --list: every device of the file, one stable line each, on stdout.
int list_devices(const Options& o) {
  auto devices = ecat::esi::list_esi_file(o.from_esi);
  if (!devices) return error(devices.error().to_string());
  for (const auto& d : *devices) std::printf("%s\n", ecat::esi::format_device_line(d).c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"ecat-esigen: ESI (ETG.2000), SII EEPROM (ETG.2010), C++ tables and device XML "
               "from one device description"};
  app.set_version_flag("--version", "ecat-esigen (ecatslave) " ECAT_VERSION);
  app.add_option("device", o.device, "device file in the ecatslave format (default: built-in generic servo)");
  app.add_option("--from-esi", o.from_esi, "import this vendor ESI instead of a device file");
  app.add_option("--product-code", o.product_code, "with --from-esi: device to take (#x.., 0x.. or decimal)");
  app.add_option("--revision", o.revision, "with --from-esi: revision to take");
  app.add_option("--type", o.type_name, "with --from-esi: device to take by its type name (Type element)");
  app.add_flag("--list", o.list, "with --from-esi: list the file's devices (type, product code, revision, name)");
  app.add_option("--esi", o.esi_out, "write the ESI XML here");
  app.add_option("--sii", o.sii_out, "write the SII EEPROM image here");
  app.add_option("--cpp", o.cpp_out, "write constexpr C++ tables here");
  app.add_option("--cpp-namespace", o.cpp_namespace, "namespace of the C++ tables");
  app.add_option("--device-xml", o.device_xml_out, "write the model as a device file in our format");
  app.add_flag("--strict", o.strict, "with --from-esi: every import warning (a repair, an element not modelled) is an error");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kExitUsage;
  }
  if (!o.device.empty() && !o.from_esi.empty()) {
    return usage_error("give either a DEVICE file or --from-esi, not both");
  }
  if (o.from_esi.empty() &&
      (!o.product_code.empty() || !o.revision.empty() || !o.type_name.empty() || o.list || o.strict)) {
    return usage_error("--product-code, --revision, --type, --list and --strict need --from-esi");
  }
  if (o.list) {
    if (!o.esi_out.empty() || !o.sii_out.empty() || !o.cpp_out.empty() || !o.device_xml_out.empty() ||
        !o.product_code.empty() || !o.revision.empty() || !o.type_name.empty()) {
      return usage_error("--list takes no selection and writes no file");
    }
    try {
      return list_devices(o);
    } catch (const std::exception& e) {
      return error(fmt::format("ecat-esigen: {}", e.what()));
    }
  }
  if (!valid_namespace(o.cpp_namespace)) {
    return usage_error(fmt::format("--cpp-namespace '{}' is not a C++ namespace name", o.cpp_namespace));
  }
  if (o.esi_out.empty() && o.sii_out.empty() && o.cpp_out.empty() && o.device_xml_out.empty()) {
    return usage_error("nothing to do: give --esi, --sii, --cpp or --device-xml");
  }
  try {
    return run(o);
  } catch (const std::exception& e) {
    return error(fmt::format("ecat-esigen: {}", e.what()));
  }
}
