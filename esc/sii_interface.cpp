#include "esc/sii_interface.hpp"
