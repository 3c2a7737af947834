// The case-file envelope: the header every kind shares, YAML errors with their line, the kind
// line, duplicate keys; the reader's helpers (hash, suggestions, ranges).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "case_test_support.hpp"
#include "rheosim/core/case.hpp"
#include "rheosim/core/config.hpp"
#include "rheosim/core/error.hpp"

namespace rheosim::core {
namespace {

using ::testing::HasSubstr;

// The error of reading the header and then checking the keys, as every reader ends.
ConfigError open_error(const std::string& text) {
  return test_support::config_error(
      [](const std::string& t) { CaseFile::parse(t, "case.yaml").check_all_keys_known(); }, text);
}

TEST(CaseFile, ReadsTheHeaderEveryKindShares) {
  const std::string text = "kind: sweep\ndescription: two points\nshear_rates: [1, 2]\n";
  const CaseFile file = CaseFile::parse(text, "cases/plate.yaml");
  EXPECT_EQ(file.header().kind, "sweep");
  EXPECT_EQ(file.header().name, "plate");  // the file's stem without `name:`
  EXPECT_EQ(file.header().description, "two points");
  EXPECT_EQ(file.header().sha256, sha256_hex(text));
  EXPECT_EQ(file.directory(), std::filesystem::path("cases"));
  // The body is the owning module's: a key no reader asked for is named.
  try {
    file.check_all_keys_known();
    ADD_FAILURE() << "shear_rates was never read";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.details().key_path, "shear_rates");
  }
}

TEST(CaseFile, MalformedYamlNamesTheLine) {
  const auto e = open_error("kind: rheometer\ngeometry: {type: parallel_plate, radius: 0.015\nfluid:\n  density: 1\n");
  EXPECT_GE(e.details().where.line, 2);
  EXPECT_THAT(e.details().problem, HasSubstr("malformed YAML"));
}

TEST(CaseFile, UnknownKindSuggestsTheNearest) {
  const auto e = open_error("kind: rheomter\n");
  EXPECT_EQ(e.details().key_path, "kind");
  EXPECT_THAT(e.details().hint, HasSubstr("'rheometer'"));
  EXPECT_THAT(e.details().expected, HasSubstr("rheometer, sweep, ldd"));
}

TEST(CaseFile, DuplicateKeyIsAnError) {
  const auto e = open_error("kind: ldd\nname: a\nname: b\n");
  EXPECT_THAT(e.details().problem, HasSubstr("appears twice"));
}

TEST(CaseFile, AReaderRefusesAKindItDoesNotRead) {
  const CaseFile file = CaseFile::parse("kind: ldd\n", "c.yaml");
  try {
    file.require_kind({"rheometer", "sweep"}, "the rheometer");
    ADD_FAILURE() << "an ldd case passed a rheometer reader's kind check";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.details().key_path, "kind");
    EXPECT_THAT(e.details().problem, HasSubstr("the rheometer reads rheometer or sweep cases, not 'ldd'"));
  }
}

TEST(Config, IncreasingListsNameTheFirstEntryOutOfOrder) {
  const Document doc = Document::from_string("rates: [1, 3, 3]\n", "case.yaml");
  const Section root = doc.root();
  const auto rates = root.numbers({"rates", "rates", "1/s"}, Range::positive());
  try {
    require_increasing(root, "rates", rates);
    ADD_FAILURE() << "a repeated entry passed";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.details().key_path, "rates");
    EXPECT_THAT(e.details().problem, HasSubstr("entry 2 (3) does not exceed entry 1 (3)"));
  }
}

TEST(Sha256, KnownVectors) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(Suggestions, NearestFindsPlausibleMisspellings) {
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(nearest("viscosty", {"viscosity", "density"}), std::optional<std::string>("viscosity"));
  EXPECT_EQ(nearest("zzz", {"viscosity", "density"}), std::nullopt);
}

TEST(Range, Rendering) {
  EXPECT_EQ(Range::open_closed(0, 2).str(), "(0, 2]");
  EXPECT_EQ(Range::positive().str(), "> 0");
  EXPECT_EQ(Range::non_negative().str(), ">= 0");
  EXPECT_FALSE(Range::open_closed(0, 2).contains(0));
  EXPECT_TRUE(Range::open_closed(0, 2).contains(2));
}

}  // namespace
}  // namespace rheosim::core
