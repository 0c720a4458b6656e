// The Profile/Dictionary part of the ESI (ETG.2000 DictionaryType): DataTypes
// for every basic type used plus one DTxxxx per ARRAY/RECORD, and Objects with
// Info (MinData/MaxData/DefaultData, little-endian hexBinary) and Flags.
#pragma once

#include <pugixml.hpp>

#include "od/dictionary.hpp"

namespace ecat::esi {

// Appends <Dictionary> to `profile`.
void append_dictionary(pugi::xml_node profile, const od::Dictionary& dictionary);

}  // namespace ecat::esi
