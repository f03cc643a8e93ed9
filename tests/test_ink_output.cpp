// Print preview's files (lib/output/ink_output.h): plate names made from ink
// names that a document chooses, which must name a file in the output's
// folder and nothing else, stay readable, and stay apart.
#include <set>
#include <string>

#include "lib/output/ink_output.h"
#include "tests/catch.h"

using namespace mpvg;

TEST_CASE("a plate's name keeps the ink's name and escapes what a file name cannot hold", "[inks][output]") {
  CHECK(plate_name("Cyan") == "Cyan");
  CHECK(plate_name("PANTONE 185 C") == "PANTONE 185 C");
  CHECK(plate_name("Gold (metallic), 50%") == "Gold (metallic), 50%25");
  CHECK(plate_name("../../../escaped") == "..%2F..%2F..%2Fescaped");
  CHECK(plate_name("a/b\\c:d*e?f\"g<h>i|j") == "a%2Fb%5Cc%3Ad%2Ae%3Ff%22g%3Ch%3Ei%7Cj");
  CHECK(plate_name(std::string("tab\there\nnul") + '\0') == "tab%09here%0Anul%00");
  CHECK(plate_name("Gr\xc3\xbcn") == "Gr\xc3\xbcn");           // UTF-8 kept
  CHECK(plate_name("Gr\xfcn") == "Gr%FCn");                    // Latin-1: not UTF-8, escaped
  CHECK(plate_name("\xc0\xaf") == "%C0%AF");                   // an overlong '/'
  CHECK(plate_name("..") == "..");  // inside "OUT(..).tif": one file name, not a folder
  for (const std::string& ink : {std::string("../x"), std::string("/etc/passwd"), std::string("a\\..\\b")})
    CHECK(plate_name(ink).find_first_of("/\\") == std::string::npos);
}

TEST_CASE("a long ink name is cut at a character and tagged with its hash", "[inks][output]") {
  const std::string a(300, 'a'), b = a + "b";
  const std::string pa = plate_name(a), pb = plate_name(b);
  CHECK(pa.size() <= kMaxPlateName);
  CHECK(pb.size() <= kMaxPlateName);
  CHECK(pa != pb);
  CHECK(pa.substr(0, 100) == a.substr(0, 100));
  CHECK(pa[pa.size() - 9] == '~');
  // Two-byte characters and escapes are never split.
  std::string wide;
  for (int i = 0; i < 100; i++) wide += "\xc3\xbc/";
  const std::string pw = plate_name(wide);
  CHECK(pw.size() <= kMaxPlateName);
  const std::string body = pw.substr(0, pw.size() - 9);
  CHECK(body.size() % 5 == 0);  // whole "ü%2F" pairs
  CHECK(body.substr(0, 5) == "\xc3\xbc%2F");
}

TEST_CASE("plate names are unique, also where a file system ignores case", "[inks][output]") {
  const std::vector<std::string> names =
      plate_names({"Cyan", "Magenta", "Yellow", "Black", "Gold", "GOLD", "gold", "gold~2", "a/b", "a%2Fb"});
  REQUIRE(names.size() == 10);
  CHECK(names[4] == "Gold");
  CHECK(names[5] == "GOLD~2");
  CHECK(names[6] == "gold~3");
  CHECK(names[7] == "gold~2~2");
  CHECK(names[8] == "a%2Fb");
  CHECK(names[9] == "a%252Fb");
  std::set<std::string> folded;
  for (std::string n : names) {
    for (char& c : n) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    folded.insert(n);
  }
  CHECK(folded.size() == names.size());
}
