// Positions in one-line vendor files, as a property over real files (issue 32
// item 2, docs/twins.md "Positions in vendor files"): a vendor ESI or ENI
// written on one line, as configurator exports are, gets every warning and
// every error of its pretty-printed original, each at the same element: the
// pretty file's line (and column) becomes the one-line file's column of that
// element. Before, everything the import said about objects, entries and PDOs
// after reading them (the repairs of the dictionary model, the refusals
// mapped back to an Object/SubItem/PDO) said "file:1".
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "esi/eni_devices.hpp"
#include "esi/eni_reader.hpp"
#include "esi/esi_reader.hpp"
#include "esi/xml_lines.hpp"

namespace ecat::esi {
namespace {

std::string data(const std::string& rel) { return std::string(ECAT_SOURCE_DIR) + "/tests/data/" + rel; }

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The file on one line: whitespace between one tag's '>' and the next '<' is
// dropped (what a configurator that writes one line leaves out), any other
// line end becomes a space (comments, multi-line texts). at[i] is where byte i
// of the original went (dropped bytes: where the next kept byte went).
struct OneLine {
  std::string text;
  std::vector<std::size_t> at;
};

OneLine collapse(const std::string& pretty) {
  OneLine o;
  o.at.assign(pretty.size() + 1, 0);
  std::size_t i = 0;
  while (i < pretty.size()) {
    if (pretty[i] == '>') {
      o.at[i] = o.text.size();
      o.text.push_back('>');
      std::size_t j = i + 1;
      while (j < pretty.size() && std::isspace(static_cast<unsigned char>(pretty[j]))) ++j;
      if (j < pretty.size() && pretty[j] == '<') {
        for (std::size_t k = i + 1; k < j; ++k) o.at[k] = o.text.size();
        i = j;
      } else {
        ++i;
      }
      continue;
    }
    const char c = pretty[i];
    o.at[i] = o.text.size();
    o.text.push_back(c == '\n' || c == '\r' ? ' ' : c);
    ++i;
  }
  o.at[pretty.size()] = o.text.size();
  return o;
}

// Byte offset in `text` of the element a position names: the column's byte,
// or, for a line alone, the line's first start tag (esi/xml_lines.hpp's rule).
std::size_t offset_of(const std::string& text, SourcePos p) {
  std::size_t start = 0;
  for (int line = 1; line < p.line; ++line) {
    std::size_t i = start;
    while (i < text.size() && text[i] != '\n' && text[i] != '\r') ++i;
    if (i + 1 < text.size() && text[i] == '\r' && text[i + 1] == '\n') ++i;
    start = i + 1;
  }
  if (p.column > 0) return start + static_cast<std::size_t>(p.column) - 1;
  for (std::size_t i = start; i + 1 < text.size() && text[i] != '\n' && text[i] != '\r'; ++i) {
    const auto next = static_cast<unsigned char>(text[i + 1]);
    if (text[i] == '<' && (std::isalpha(next) || next == '_' || next == ':')) return i;
  }
  return start;
}

// Where the one-line file must name what the pretty file names at `p`.
std::string expected_position(const std::string& pretty, const OneLine& one, SourcePos p) {
  if (p.line == 0) return "0";
  const std::size_t off = offset_of(pretty, p);
  return LineIndex(one.text).position_of(static_cast<std::ptrdiff_t>(one.at[off])).to_string();
}

void expect_same_warnings(const std::string& pretty, const OneLine& one, const std::vector<EsiWarning>& want,
                          const std::vector<EsiWarning>& got, const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  int with_column = 0;
  for (std::size_t k = 0; k < want.size(); ++k) {
    EXPECT_EQ(got[k].element, want[k].element) << what << " #" << k;
    EXPECT_EQ(got[k].message, want[k].message) << what << " #" << k;
    EXPECT_EQ(got[k].line.to_string(), expected_position(pretty, one, want[k].line))
        << what << " #" << k << ": " << want[k].to_string("pretty") << "\n  one line: " << got[k].to_string("one");
    if (got[k].line.column > 0) ++with_column;
  }
  // Every warning at an element inside the root says which by its column.
  int positioned = 0;
  for (const auto& w : want) positioned += w.line.line > 1 ? 1 : 0;
  EXPECT_EQ(with_column, positioned) << what;
}

// The ESI files whose import repairs most kinds of things in the dictionary
// model (1018h, 1C12h/1C13h and mapping defaults, mapping flags, mapping entry
// types, created process-data objects, STRING defaults, DefaultString sizes,
// decimal indices, placeholder entries, SM sizes), and three it refuses: at
// a TxPdo and an RxPdo (a PDO that maps its own index, known-limits.txt) and
// at a SubItem.
const char* const kEsiFiles[] = {
    "esi-mismatch/placeholder-entry.xml",
    "esi-mismatch/pdo-larger-than-sm.xml",
    "esi-mismatch/decimal-index.xml",
    "esi-mismatch/string-default-bytes.xml",
    "esi-vendor/diebie-bp-ges.xml",
    "esi-vendor/rtlabs-linux-lan9252.xml",
    "esi-vendor/wandercraft-freedom-k64f.xml",
    "esi-vendor/smc-ex250-sen1.xml",
    "esi-vendor/weidmueller-ur20-fbc-igh.xml",
    "esi-vendor/march-pdbm4.xml",
    "esi-vendor/pollen-orbita2d.xml",
};

TEST(OneLineCorpusPositions, EveryEsiWarningAndErrorNamesTheSameElementOnOneLine) {
  int warnings_seen = 0;
  int errors_seen = 0;
  for (const char* rel : kEsiFiles) {
    const std::string pretty = slurp(data(rel));
    ASSERT_FALSE(pretty.empty()) << rel;
    const OneLine one = collapse(pretty);
    ASSERT_EQ(one.text.find('\n'), std::string::npos) << rel;
    std::vector<EsiWarning> want;
    std::vector<EsiWarning> got;
    auto a = read_esi_string(pretty, rel, EsiSelection{}, &want);
    auto b = read_esi_string(one.text, rel, EsiSelection{}, &got);
    ASSERT_EQ(static_cast<bool>(a), static_cast<bool>(b)) << rel;
    if (!a) {
      EXPECT_EQ(b.error().message, a.error().message) << rel;
      EXPECT_EQ(b.error().line.to_string(), expected_position(pretty, one, a.error().line))
          << rel << ": " << a.error().to_string() << "\n  one line: " << b.error().to_string();
      if (a.error().line.line > 1) {
        EXPECT_GT(b.error().line.column, 0) << b.error().to_string();
      }
      ++errors_seen;
    }
    expect_same_warnings(pretty, one, want, got, rel);
    warnings_seen += static_cast<int>(want.size());
  }
  // The files above do give what the test is about.
  EXPECT_GE(warnings_seen, 40);
  EXPECT_EQ(errors_seen, 3);
}

// The configurator-exported ENI of tests/data/eni (kpierczy/ethercat-lib), on
// one line as acontis' EniEngine writes it, run without an ESI: the warnings
// of its synthesised devices and the refusal of the Elmo drive's SM layout
// are at the same elements as in the pretty file.
TEST(OneLineCorpusPositions, EniWithoutEsiNamesTheSameElementsOnOneLine) {
  for (const char* rel : {"eni/kpierczy-elmo-wheels.xml", "eni/servo-and-io.xml", "eni/soem-sample-eni.xml"}) {
    const std::string pretty = slurp(data(rel));
    const OneLine one = collapse(pretty);
    std::vector<EsiWarning> want;
    std::vector<EsiWarning> got;
    auto a = read_eni_string(pretty, rel, &want);
    auto b = read_eni_string(one.text, rel, &got);
    ASSERT_TRUE(a) << a.error().to_string();
    ASSERT_TRUE(b) << b.error().to_string();
    auto da = eni_devices(*a, {}, &want);
    auto db = eni_devices(*b, {}, &got);
    ASSERT_EQ(static_cast<bool>(da), static_cast<bool>(db)) << rel;
    if (!da) {
      EXPECT_EQ(db.error().message, da.error().message) << rel;
      EXPECT_EQ(db.error().line.to_string(), expected_position(pretty, one, da.error().line))
          << rel << ": " << da.error().to_string() << "\n  one line: " << db.error().to_string();
      EXPECT_GT(db.error().line.column, 0) << db.error().to_string();
    } else {
      // Every object, entry and PDO of a synthesised device is placed in the
      // ENI (the device's source file), at the same element.
      for (std::size_t s = 0; s < da->size(); ++s) {
        const od::DeviceDescription& pa = (*da)[s].device;
        const od::DeviceDescription& pb = (*db)[s].device;
        if (!(*da)[s].esi_file.empty()) continue;
        EXPECT_EQ(pb.source_file, rel);
        ASSERT_EQ(pa.dictionary.size(), pb.dictionary.size());
        for (std::size_t k = 0; k < pa.dictionary.size(); ++k) {
          const od::Object& oa = pa.dictionary.objects()[k];
          const od::Object& ob = pb.dictionary.objects()[k];
          EXPECT_EQ(ob.source_line.to_string(), expected_position(pretty, one, oa.source_line))
              << rel << " slave " << s + 1 << " object " << oa.index;
        }
      }
    }
    expect_same_warnings(pretty, one, want, got, rel);
  }
}


// The same, as exact messages: an Object repair, a refusal at a PDO and an ENI
// slave's refusal, each at its element's column on line 1.
TEST(OneLineCorpusPositions, ExactMessagesOfOneLineFiles) {
  const OneLine s = collapse(slurp(data("esi-mismatch/string-default-bytes.xml")));
  std::vector<EsiWarning> w;
  ASSERT_TRUE(read_esi_string(s.text, "s.xml", EsiSelection{}, &w));
  const std::size_t object = s.text.rfind("<Object>", s.text.find("<Index>#x2003<"));
  const std::string repair = "s.xml:1:" + std::to_string(object + 1) +
                             ": warning: Object: the object's name holds the byte 01h at 4, a character XML 1.0 "
                             "forbids; the twin has 'Name?with a control character'";
  std::vector<std::string> got;
  for (const auto& x : w) got.push_back(x.to_string("s.xml"));
  EXPECT_NE(std::find(got.begin(), got.end(), repair), got.end()) << repair << "\n" << ::testing::PrintToString(got);

  const OneLine p = collapse(slurp(data("esi-vendor/pollen-orbita2d.xml")));
  auto refused = read_esi_string(p.text, "p.xml");
  ASSERT_FALSE(refused);
  const std::size_t pdo = p.text.rfind("<TxPdo", p.text.find("<Index>#x1800<"));
  EXPECT_EQ(refused.error().to_string(),
            "p.xml:1:" + std::to_string(pdo + 1) +
                ": SubItem: 603Fh:00 has type UNSIGNED16 but must be UNSIGNED8 (the twin cannot represent this; the "
                "import refuses it)");

  const OneLine e = collapse(slurp(data("eni/kpierczy-elmo-wheels.xml")));
  auto net = read_eni_string(e.text, "net.xml");
  ASSERT_TRUE(net) << net.error().to_string();
  auto devs = eni_devices(*net, {});
  ASSERT_FALSE(devs);
  // Slave 2's Sm3, where its SM2's three buffers (as the ENI places them) end.
  const std::size_t sm3 = e.text.find("<Sm3>", e.text.find("WheelRearLeft"));
  EXPECT_EQ(devs.error().to_string(), "net.xml:1:" + std::to_string(sm3 + 1) +
                                          ": slave 2 (WheelRearLeft): SyncManager 3 (0x1180..0x134d) overlaps "
                                          "SyncManager 2 (0x1100..0x12c7)");
}

}  // namespace
}  // namespace ecat::esi
