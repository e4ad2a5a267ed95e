// scene_key_docs.hpp — the key tables of docs/config.md, generated from scene_keys.hpp: key,
// symbol, unit, default (the field's in-class value), allowed values and meaning. The tables
// sit in the document between marker lines; app/scene_key_docs.cpp rewrites or checks them,
// and a test of the default run fails when the document's copy is stale.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace cdpowder {

/// The TOML tables that have keys ("system", "contact", "contact.wall", …), in file order.
std::vector<std::string> scene_key_tables();

/// The markdown key table of one TOML table ("solver"), header rows included; "" when the
/// table has no keys.
std::string scene_key_table_markdown(std::string_view table);

/// The line that opens the generated block of `table` in a document, and the one closing it.
std::string generated_block_start(std::string_view table);
inline constexpr std::string_view kGeneratedBlockEnd = "<!-- end generated -->";

/// `markdown` with each generated block's content replaced by its table as generated now; the
/// rest is kept byte for byte. Throws std::invalid_argument when a block is not closed,
/// names a table without keys, or a table with keys has no block or two.
std::string with_generated_key_tables(std::string_view markdown);

}  // namespace cdpowder
