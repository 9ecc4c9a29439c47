// docs/cpp.md, "Reading files": the page's example as written, run in examples/data (ctest's
// working directory); quartz is space group 154, as the page's comment says.
#include "reading_files_includes.inc"

#include "doc_check.hpp"

int main() {
#include "reading_files_block.inc"

    DOC_CHECK(group.number == 154, "group.number == 154");
    DOC_CHECK(s.positions.size() == 9, "the unit cell of quartz holds 9 atoms");
    return 0;
}
