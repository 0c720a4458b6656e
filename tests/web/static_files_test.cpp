// The page's files (web/static_files.hpp): a URL path maps below the page's
// directory only through plain names; traversal and hidden files are refused.
#include <gtest/gtest.h>

#include <cstdlib>

#include "web/static_files.hpp"

namespace ecat::test {
namespace {

using web::resolve_static;

TEST(WebStaticFiles, RootIsTheIndexAndNamesMapBelowTheDirectory) {
  EXPECT_EQ(resolve_static("/srv/www", "/"), "/srv/www/index.html");
  EXPECT_EQ(resolve_static("/srv/www", "/app.js"), "/srv/www/app.js");
  EXPECT_EQ(resolve_static("/srv/www", "/img/tree-1.svg"), "/srv/www/img/tree-1.svg");
}

TEST(WebStaticFiles, TraversalHiddenFilesAndOddCharactersAreRefused) {
  for (const char* bad : {"/..", "/../etc/passwd", "/a/../../b", "/./index.html", "/.git/config", "//etc/passwd",
                          "/a//b", "/dir/", "/a\\..\\b", "/a b", "/%2e%2e", "relative.html", ""}) {
    EXPECT_EQ(resolve_static("/srv/www", bad), std::nullopt) << bad;
  }
}

TEST(WebStaticFiles, ContentTypesByExtension) {
  EXPECT_EQ(web::content_type("/x/index.html"), "text/html; charset=utf-8");
  EXPECT_EQ(web::content_type("app.js"), "text/javascript; charset=utf-8");
  EXPECT_EQ(web::content_type("style.css"), "text/css; charset=utf-8");
  EXPECT_EQ(web::content_type("shot.png"), "image/png");
  EXPECT_EQ(web::content_type("README"), "application/octet-stream");
}

TEST(WebStaticFiles, TheOptionWinsThenTheEnvironmentThenBesideTheProgram) {
  ::unsetenv("ECAT_WWW_DIR");
  EXPECT_EQ(web::find_www_dir("", "/usr/bin"), "/usr/bin/../share/ecatslave/www");
  ::setenv("ECAT_WWW_DIR", "/tmp/page", 1);
  EXPECT_EQ(web::find_www_dir("", "/usr/bin"), "/tmp/page");
  EXPECT_EQ(web::find_www_dir("/opt/www", "/usr/bin"), "/opt/www");
  ::unsetenv("ECAT_WWW_DIR");
}

}  // namespace
}  // namespace ecat::test
