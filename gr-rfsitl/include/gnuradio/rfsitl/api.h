#pragma once
/// Symbol visibility for libgnuradio-rfsitl (the library is built with hidden
/// visibility so only the block interfaces are exported).
#include <gnuradio/attributes.h>

#ifdef gnuradio_rfsitl_EXPORTS
#define RFSITL_API __GR_ATTR_EXPORT
#else
#define RFSITL_API __GR_ATTR_IMPORT
#endif
