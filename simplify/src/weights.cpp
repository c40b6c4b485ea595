#include "ddsimp/ddsimp.h"
