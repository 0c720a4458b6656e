// Generator cost (issue 8 item 1): time and peak memory to load a device
// file and emit its ESI and SII, for every seed device in xml/devices/ and
// for synthetic devices of 1,000 / 10,000 / 100,000 objects.
//
// Synthetic device: generic-servo.xml with N extra manufacturer objects
// (2000h.., UNSIGNED32 rw with name, min, max, default). The 16-bit index
// space has room for 16,384 manufacturer objects (2000h-5FFFh), so beyond
// that the N entries come as ARRAY objects of ceil(N/16384) elements each:
// 100,000 = 14,286 ARRAYs x 7 elements (N counts dictionary entries then).
//
// Peak memory: each case is also run once in a fresh child process
// (this program re-executed with --peak), which reports VmHWM minus VmRSS
// just before the generator ran - every allocator (libxml2, pugixml, C++).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "esi/device_loader.hpp"
#include "esi/esi_writer.hpp"
#include "esi/sii_writer.hpp"

namespace ecat::bench {
namespace {

namespace fs = std::filesystem;
constexpr std::size_t kManufacturerIndices = 0x6000 - 0x2000;
constexpr unsigned kFirstIndex = 0x2000;

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + p.string());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path devices_dir() { return fs::path(ECAT_SOURCE_DIR) / "xml" / "devices"; }

std::string synthetic_device(std::size_t entries) {
  std::string xml = read_file(devices_dir() / "generic-servo.xml");
  const std::size_t per = (entries + kManufacturerIndices - 1) / kManufacturerIndices;
  const std::size_t objects = (entries + per - 1) / per;
  std::string extra;
  extra.reserve(objects * 160);
  char buf[256];
  for (std::size_t i = 0; i < objects; ++i) {
    const unsigned index = kFirstIndex + static_cast<unsigned>(i);
    if (per == 1) {
      std::snprintf(buf, sizeof buf,
                    "    <Object index=\"#x%04X\" name=\"Parameter %zu\" type=\"UNSIGNED32\" access=\"rw\" "
                    "min=\"0\" max=\"1000000\" default=\"%zu\"/>\n",
                    index, i, i % 1000);
    } else {
      std::snprintf(buf, sizeof buf,
                    "    <Object index=\"#x%04X\" name=\"Table %zu\" code=\"ARRAY\" type=\"UNSIGNED32\" "
                    "access=\"rw\" count=\"%zu\" default=\"%zu\"/>\n",
                    index, i, per, i % 1000);
    }
    extra += buf;
  }
  const std::size_t at = xml.find("</Objects>");
  if (at == std::string::npos) throw std::runtime_error("generic-servo.xml has no </Objects>");
  xml.insert(at, extra);
  return xml;
}

// Load + ESI + SII: what the generator does for one device. Returns output bytes.
std::size_t generate(const std::string& xml, const std::string& name) {
  auto dev = esi::load_device_string(xml, name);
  if (!dev) throw std::runtime_error(dev.error().to_string());
  const std::string esi_text = esi::write_esi(*dev);
  auto sii = esi::write_sii(*dev);
  if (!sii) throw std::runtime_error(sii.error());
  return esi_text.size() + sii->size();
}

std::string input_for(const std::string& kind, const std::string& arg) {
  if (kind == "seed") return read_file(devices_dir() / (arg + ".xml"));
  return synthetic_device(std::stoul(arg));
}

long status_kib(const char* field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::string key = std::string(field) + ":";
  while (std::getline(in, line)) {
    if (line.rfind(key, 0) == 0) return std::stol(line.substr(key.size()));
  }
  return -1;
}

// Child side of the peak measurement: prints the peak in KiB.
int measure_peak(const std::string& kind, const std::string& arg) {
  const std::string xml = input_for(kind, arg);
  const std::string name = (devices_dir() / "input.xml").string();
  const long before = status_kib("VmRSS");
  generate(xml, name);
  std::printf("%ld\n", status_kib("VmHWM") - before);
  return 0;
}

double peak_mib(const std::string& kind, const std::string& arg) {
  const std::string cmd = "/proc/" + std::to_string(::getpid()) + "/exe --peak " + kind + " " + arg;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return -1;
  long kib = -1;
  if (std::fscanf(p, "%ld", &kib) != 1) kib = -1;
  ::pclose(p);
  return kib < 0 ? -1.0 : static_cast<double>(kib) / 1024.0;
}

void run(benchmark::State& state, const std::string& kind, const std::string& arg) {
  const std::string xml = input_for(kind, arg);
  const std::string name = (devices_dir() / "input.xml").string();
  std::size_t out = 0;
  for (auto _ : state) benchmark::DoNotOptimize(out = generate(xml, name));
  state.counters["input_KiB"] = static_cast<double>(xml.size()) / 1024.0;
  state.counters["output_KiB"] = static_cast<double>(out) / 1024.0;
  static std::map<std::string, double> peaks;  // one child per case, not per run
  auto [it, fresh] = peaks.try_emplace(kind + arg, 0.0);
  if (fresh) it->second = peak_mib(kind, arg);
  state.counters["peak_MiB"] = it->second;
}

void register_all() {
  std::vector<std::string> seeds;
  for (const auto& e : fs::directory_iterator(devices_dir())) {
    if (e.path().extension() == ".xml") seeds.push_back(e.path().stem().string());
  }
  std::sort(seeds.begin(), seeds.end());
  for (const auto& s : seeds) {
    benchmark::RegisterBenchmark(("BM_Generator_Seed/" + s).c_str(),
                                 [s](benchmark::State& st) { run(st, "seed", s); })
        ->Unit(benchmark::kMillisecond);
  }
  for (std::size_t n : {1000u, 10000u, 100000u}) {
    benchmark::RegisterBenchmark(("BM_Generator_Synthetic/" + std::to_string(n)).c_str(),
                                 [n](benchmark::State& st) { run(st, "synthetic", std::to_string(n)); })
        ->Unit(benchmark::kMillisecond);
  }
}

}  // namespace
}  // namespace ecat::bench

int main(int argc, char** argv) {
  if (argc == 4 && std::string(argv[1]) == "--peak") return ecat::bench::measure_peak(argv[2], argv[3]);
  ecat::bench::register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
