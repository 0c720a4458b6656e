// XML 1.0 §2.2 Char: what a well-formed document may hold. #x9, #xA, #xD,
// #x20-#xD7FF, #xE000-#xFFFD, #x10000-#x10FFFF, as UTF-8 (the encoding both
// writers declare). Every other code point (C0 controls, surrogates, FFFE/
// FFFF) and every byte that is not part of a valid UTF-8 sequence is
// forbidden, even as a character reference (&#1; is not well-formed either).
// The import repairs such text with a warning (docs/twins.md "Import
// policy"); the writers pass every text and attribute through
// xml_safe_text() as the last guard, so they never write a forbidden
// character.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace pugi {
class xml_document;
}

namespace ecat::esi {

// Byte offset of the first forbidden character or invalid UTF-8 byte.
std::optional<std::size_t> find_forbidden_xml_char(std::string_view text) noexcept;

// `text` with each forbidden character (each byte of an invalid UTF-8
// sequence) replaced by '?': one byte for one, so a string keeps its length.
std::string xml_safe_text(std::string_view text);

// Every attribute value, text and comment of `doc` through xml_safe_text();
// a text's CR LF and lone CR become LF (XML 1.0 §2.11: a parser reads them
// so, in element text they would not round-trip).
void make_xml_safe(pugi::xml_document& doc);

}  // namespace ecat::esi
