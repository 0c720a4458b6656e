// The page's files (issue 27): plain HTML/CSS/JS from share/ecatslave/www,
// served as they are. A URL path maps to a file below that directory only
// when every segment is a plain name ([A-Za-z0-9._-], not starting with a
// dot): "..", hidden files, backslashes and encoded tricks are refused
// before the file system is asked.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace ecat::web {

// The file below `root` for URL path `path` ("/" is index.html), or empty
// when the path is refused.
std::optional<std::string> resolve_static(std::string_view root, std::string_view path);
// The Content-Type for a file name by its extension (application/octet-stream otherwise).
std::string_view content_type(std::string_view file);
// The directory of the page: `option` (--http-root) if given, else
// $ECAT_WWW_DIR, else share/ecatslave/www next to the program (installed:
// BINDIR/../share; build tree: build/bin/../share, a link to web/www).
std::string find_www_dir(std::string_view option, std::string_view program_dir);

}  // namespace ecat::web
