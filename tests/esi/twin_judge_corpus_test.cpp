// The one-judge property (issue 32 item 1 (a), docs/twins.md "One judge") over
// every device of every ESI in tests/data: what the import accepts reaches a
// fixed point of the device-file writer and of the ESI writer, well-formed;
// what it refuses, it refuses with the vendor file's name and a line. With
// xmllint, every written device file is valid against xml/schema/device.xsd
// and every written ESI against the ETG.2000 schemas (one xmllint run per
// corpus file and schema).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "esi/esi_device_list.hpp"
#include "esi/esi_reader.hpp"
#include "esi/twin_judge.hpp"
#include "esi_xmllint.hpp"

namespace ecat::esi {
namespace {

namespace fs = std::filesystem;

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// xmllint over several files at once; "" when all validate.
std::string validate_all(const std::vector<std::string>& files, const std::string& schema) {
  if (files.empty()) return {};
  std::string cmd = "xmllint --noout --schema '" + schema + "'";
  for (const auto& f : files) cmd += " '" + f + "'";
  cmd += " 2>&1";
  std::string out;
  if (FILE* p = popen(cmd.c_str(), "r")) {
    char buf[4096];
    while (std::size_t n = fread(buf, 1, sizeof buf, p)) out.append(buf, n);
    if (pclose(p) == 0) return {};
  }
  return out.empty() ? "xmllint failed" : out.substr(0, 4000);
}

// The corpus files whose chain fails for a listed reason
// (tests/twins/known-limits.txt, "file|reason"): a device the import refuses
// must be of one of them, so no corpus file fails the import without one.
std::map<std::string, std::string> known_limits() {
  std::map<std::string, std::string> out;
  std::istringstream in(read_text(fs::path(ECAT_SOURCE_DIR) / "tests" / "twins" / "known-limits.txt"));
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    const auto bar = line.find('|');
    if (bar != std::string::npos && bar + 1 < line.size()) out[line.substr(0, bar)] = line.substr(bar + 1);
  }
  return out;
}

struct Tally {
  int files = 0, devices = 0, judged = 0, refused = 0, stable_first = 0, passive = 0, unselectable = 0;
};

void judge_file(const fs::path& file, Tally& t, std::vector<std::string>& device_files,
                std::vector<std::string>& esi_files) {
  SCOPED_TRACE(file.filename().string());
  const std::string xml = read_text(file);
  auto list = list_esi_devices(xml, file.string());
  ASSERT_TRUE(list) << list.error().to_string();
  ++t.files;
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> seen;
  std::set<std::tuple<std::uint32_t, std::uint32_t, std::string>> seen_typed;
  int n = 0;
  for (const auto& dev : *list) {
    ++n;
    ++t.devices;
    // A device without a product code has no EtherCAT slave controller
    // (passive terminals): nothing for a master to see (twin_chain.sh).
    if (!dev.product_code) {
      ++t.passive;
      continue;
    }
    EsiSelection sel{dev.product_code, dev.revision, std::nullopt};
    const auto key = std::make_pair(*dev.product_code, dev.revision.value_or(0));
    if (seen[key]++ > 0) sel.type_name = dev.type;
    if (!seen_typed.insert({key.first, key.second, dev.type}).second) {
      ++t.unselectable;
      continue;
    }
    SCOPED_TRACE(describe_device(dev));
    std::vector<EsiWarning> warnings;
    auto d = read_esi_string(xml, file.string(), sel, &warnings);
    if (!d) {
      // Refused: at the vendor file, with a line.
      ++t.refused;
      std::printf("refused: %s: %s\n", describe_device(dev).c_str(), d.error().to_string().c_str());
      EXPECT_EQ(d.error().file, file.string());
      EXPECT_GT(d.error().line, 0) << d.error().to_string();
      static const std::map<std::string, std::string> listed = known_limits();
      EXPECT_TRUE(listed.count(file.filename().string()))
          << d.error().to_string() << ": refused, and the file is not in tests/twins/known-limits.txt with a reason";
      continue;
    }
    for (const auto& w : warnings) {
      EXPECT_GT(w.line, 0) << w.to_string(file.string());
      // The repairs of issue 32 item 2, listed where the vendor corpus meets them.
      for (const char* kind : {"has BitLen 0", "is shorter than the PDOs assigned", "is decimal by ETG.2000",
                               "STRING default", "a character XML 1.0 forbids", "the device has no Name",
                               "is longer than the PDOs assigned"}) {
        if (w.message.find(kind) != std::string::npos) {
          std::printf("issue-32 repair: %s\n", w.to_string(file.string()).c_str());
        }
      }
    }
    auto judged = judge_twin(*d);
    if (!judged) {
      ADD_FAILURE() << judged.error();
      continue;
    }
    ++t.judged;
    if (judged->first_write_stable) ++t.stable_first;
    if (test::have_xmllint()) {
      const std::string stem = fmt::format("judge_{}_{}", file.stem().string(), n);
      device_files.push_back(test::write_test_file(stem + ".device.xml", judged->device_xml));
      esi_files.push_back(test::write_test_file(stem + ".esi.xml", judged->esi));
    }
  }
}

void judge_dir(const fs::path& dir, Tally& t) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() == ".xml" && read_text(e.path()).find("<EtherCATInfo") != std::string::npos) {
      files.push_back(e.path());
    }
  }
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    std::vector<std::string> device_files, esi_files;
    judge_file(f, t, device_files, esi_files);
    if (!test::have_xmllint()) continue;
    SCOPED_TRACE(f.filename().string());
    EXPECT_EQ(validate_all(device_files, std::string(ECAT_SOURCE_DIR) + "/xml/schema/device.xsd"), "");
    if (test::can_validate_esi()) {
      for (const auto& schema : test::esi_schemas()) EXPECT_EQ(validate_all(esi_files, schema), "");
    }
    for (const auto& p : device_files) fs::remove(p);
    for (const auto& p : esi_files) fs::remove(p);
  }
}

TEST(TwinJudge, EveryDeviceOfEveryCorpusFileReachesAFixedPoint) {
  Tally t;
  const fs::path data = fs::path(ECAT_SOURCE_DIR) / "tests" / "data";
  judge_dir(data / "esi-vendor", t);
  judge_dir(data / "esi", t);
  judge_dir(data / "esi-mismatch", t);
  std::printf("one judge: %d files, %d devices: %d judged (%d already stable on the first write), "
              "%d refused at the vendor line, %d passive, %d not selectable\n",
              t.files, t.devices, t.judged, t.stable_first, t.refused, t.passive, t.unselectable);
  // The corpus as of issue 32: 70 vendor ESI files, tests/data/esi, tests/data/esi-mismatch.
  EXPECT_GE(t.files, 75);
  EXPECT_EQ(t.devices, t.judged + t.refused + t.passive + t.unselectable);
  if (!test::can_validate_esi()) GTEST_LOG_(INFO) << "ESI schema not validated: " << test::why_no_esi_schema();
}

}  // namespace
}  // namespace ecat::esi
