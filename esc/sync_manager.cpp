#include "esc/sync_manager.hpp"
