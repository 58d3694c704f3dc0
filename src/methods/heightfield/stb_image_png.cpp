// The PNG decoder of stb_image (Debian's libstb-dev), compiled from its header here rather than
// linked from libstb.so: built with the library's flags, the fuzz target's coverage and
// AddressSanitizer reach into it, and no decoder of another format is there to be reached by a
// file that only pretends to be a height map. Under the sanitizers this file is built without
// UndefinedBehaviorSanitizer (src/CMakeLists.txt): stb_image hands memcpy a null pointer for an
// empty chunk, harmless but reported, in code this project cannot change.
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_NO_STDIO
#include <stb/stb_image.h>
