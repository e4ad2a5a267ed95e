# Warnings every target of ours links through `cdpowder_warnings`.
add_library(cdpowder_warnings INTERFACE)
target_compile_options(cdpowder_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wold-style-cast
  -Wimplicit-fallthrough -Wnull-dereference)
# No fused multiply-add contraction: the same seed gives the same bits whatever -march says.
add_compile_options(-ffp-contract=off)
