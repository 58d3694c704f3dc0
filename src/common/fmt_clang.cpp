// Debian's libfmt is built by GCC. Clang mangles the signature of fmt::detail::vformat_to<char>
// (its argument type is written through an alias template) differently, so a clang build finds no
// such symbol in the library. Each file that includes only <fmt/core.h> calls it, so it is
// instantiated here once, under clang's name; the rest of fmt still comes from the library.
#if defined(__clang__)
#include <fmt/format.h>

template void fmt::detail::vformat_to<char>(fmt::detail::buffer<char>&, fmt::string_view,
                                            fmt::format_args, fmt::detail::locale_ref);
#endif
