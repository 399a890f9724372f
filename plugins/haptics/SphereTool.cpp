#include "plugins/haptics/SphereTool.h"
