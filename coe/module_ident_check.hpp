// The Modular Device Profile's module check (ETG.5001.1; AL status code
// 0070h, ETG.1000.6 Table 11 "Detected module ident list does not match"):
// a master that configured the modules writes their idents to F030h in PreOp;
// on PreOp -> SafeOp the slave compares that list with the modules it
// detected (F050h) and refuses SafeOp when they differ. docs/esi-sii.md
// "Modular devices" records the decisions (an empty F030h means "not
// configured": no check; the lists must agree in length and in every entry).
#pragma once

#include "coe/object_store.hpp"
#include "esc/al_status_code.hpp"

namespace ecat::coe {

// NoError for a device without F030h/F050h or with F030h:00 = 0;
// DetectedModuleIdentListMismatch when the lists differ.
esc::AlStatusCode check_module_idents(const ObjectStore& store) noexcept;

}  // namespace ecat::coe
