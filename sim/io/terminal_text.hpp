#pragma once
// Text from files and the command line (file names, names, attribute values in reasons) as a
// terminal shows it harmlessly: a file name must not move the cursor, recolour the screen,
// retitle the window or hide the rest of a line (ESC [ ..., OSC ..., CR, BS).
#include <string>
#include <string_view>

namespace jam {

/// `text` with every control character written out: C0 (below 0x20, tab and newline included:
/// a message stays one line) and DEL as \xNN, the C1 controls as UTF-8 encodes them
/// (U+0080-U+009F) as \u00NN, and bytes that are not valid UTF-8 as \xNN. Other text, UTF-8
/// included, is kept as it is.
std::string visible(std::string_view text);

}  // namespace jam
