#include "esi/device_loader.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "esi/device_build.hpp"
#include "esi/device_failure.hpp"
#include "esi/device_parse.hpp"
#include "esi/xml_embedded.hpp"

namespace ecat::esi {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kEmbeddedPrefix = "embedded:";
constexpr std::string_view kProfilesDir = "profiles";

// One file to read: its name in messages, where its includes are resolved
// (a directory on disk, or a folder of the embedded files) and its text.
struct Source {
  std::string name;  // in messages
  std::string id;    // identity for cycle detection (canonical path)
  bool embedded = false;
  fs::path base;  // directory on disk, or embedded folder ("devices")
  std::string text;
};

std::optional<std::string> read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream ss;
  ss << in.rdbuf();
  return std::move(ss).str();
}

std::optional<Source> embedded_source(const fs::path& relative) {
  const std::string key = relative.lexically_normal().generic_string();
  auto text = find_embedded(key);
  if (!text) return std::nullopt;
  std::string name = std::string(kEmbeddedPrefix) + key;
  return Source{name, name, true, relative.parent_path(), std::string(*text)};
}

Source disk_source(const fs::path& path, std::string text) {
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(path, ec);
  return Source{path.string(), (ec ? path : canonical).string(), false, path.parent_path(),
                std::move(text)};
}

class Loader {
 public:
  od::DeviceDescription load(Source root) {
    read(std::move(root));
    return build_device(std::move(spec_));
  }

 private:
  void read(Source src) {
    stack_.push_back(src.id);
    const Source& s = src;
    parse_device_text(s.text, s.name, schema_, spec_,
                      [&](const Where& w, std::string_view href) { include(s, w, href); });
    stack_.pop_back();
  }

  void include(const Source& from, const Where& w, std::string_view href) {
    std::optional<Source> next = resolve(from, w, href);
    if (std::find(stack_.begin(), stack_.end(), next->id) != stack_.end()) {
      fail_at(w, fmt::format("include cycle: '{}' includes itself (via {})", href, next->name));
    }
    read(std::move(*next));
  }

  std::optional<Source> resolve(const Source& from, const Where& w, std::string_view href) {
    const fs::path rel(href);
    if (from.embedded) {
      if (auto e = embedded_source(from.base / rel)) return e;
      fail_at(w, fmt::format("include file '{}' not found among the built-in files", href));
    }
    const fs::path path = (from.base / rel).lexically_normal();
    if (auto text = read_file(path)) return disk_source(path, std::move(*text));
    // "../profiles/NAME.xml" not on disk: the built-in profile.
    if (rel.has_parent_path() && rel.parent_path().filename() == kProfilesDir) {
      if (auto e = embedded_source(fs::path(kProfilesDir) / rel.filename())) return e;
    }
    fail_at(w, fmt::format("include file '{}' not found (looked for {})", href, path.string()));
  }

  SchemaValidator schema_{find_embedded(kEmbeddedSchema).value_or(std::string_view{})};
  DeviceSpec spec_;
  std::vector<std::string> stack_;
};

Expected<od::DeviceDescription, LoadError> run(Source root, std::string source_file) {
  const std::string name = root.name;
  try {
    od::DeviceDescription dev = Loader{}.load(std::move(root));
    dev.source_file = std::move(source_file);
    return dev;
  } catch (const LoadFailure& f) {
    return fail(f.error);
  } catch (const std::exception& e) {
    return fail(LoadError{name, 0, e.what()});
  }
}

}  // namespace

Expected<od::DeviceDescription, LoadError> load_device_file(const fs::path& path) {
  auto text = read_file(path);
  if (!text) return fail(LoadError{path.string(), 0, "cannot open the device file"});
  return run(disk_source(path, std::move(*text)), path.string());
}

Expected<od::DeviceDescription, LoadError> load_device_string(std::string_view xml,
                                                              std::string_view name) {
  return run(disk_source(fs::path(name), std::string(xml)), std::string(name));
}

Expected<od::DeviceDescription, LoadError> load_default_device() {
  auto src = embedded_source(fs::path(kEmbeddedDefaultDevice));
  if (!src) {
    return fail(LoadError{std::string(kEmbeddedDefaultDevice), 0,
                          "the default device is not built into this program"});
  }
  std::string name = src->name;
  return run(std::move(*src), std::move(name));
}

}  // namespace ecat::esi
