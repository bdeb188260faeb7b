/* xxHash's implementation, compiled once (Debian's libxxhash-dev header).
   Third-party code: built without the project's strict warnings. */
#define XXH_STATIC_LINKING_ONLY
#define XXH_IMPLEMENTATION
#include <xxhash.h>
