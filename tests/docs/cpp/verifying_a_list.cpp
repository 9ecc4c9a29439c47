// docs/cpp.md, "Verifying a list": the page's example as written, on a list tricell computed;
// verify() must accept it.
#include "verifying_a_list_includes.inc"

#include <iostream>

#include "doc_check.hpp"
#include "silicon.hpp"

int main() {
    const auto positions = doc::silicon();
    const auto box = tricell::Box::from_parameters(5.43, 5.43, 5.43, 90, 90, 90);
    tricell::NeighborOptions options;
    options.cutoff = 4.0;
    options.half = true;
    const tricell::NeighborList list = tricell::compute_neighbors(box, positions, options);

#include "verifying_a_list_block.inc"

    DOC_CHECK(report.ok, "a list tricell computed is verified");
    DOC_CHECK(report.message.rfind("ok: ", 0) == 0, "the message starts with ok: ");
    return 0;
}
