// torch.ops.tricell.pair_vectors: the vectors D = positions[j] - positions[i] + S @ cells[s] of
// the pairs of each structure s of a batch (structure s owns pairs offsets[s]:offsets[s + 1])
// and their lengths d = |D|, with gradients through the positions and every cell.
//
// The forward pass is one loop over the pairs in the dtype of the positions (float32 or
// float64), each pair reading its two positions and its structure's three lattice vectors, so
// no per-pair copy of a cell is ever made (torch's own ops would gather a cell per pair, and its
// norm over a dimension of three is many times slower than the loop). The backward pass first
// folds d's gradient into D's (g_D + g_d D / d, nothing where d = 0: two atoms at one place),
// then, D being linear in the positions and the cells, maps it to (index_add at j minus at i,
// and per structure the sum of S_p g_p^T over its pairs). It is written with ordinary torch ops,
// which are recorded when a second derivative is asked for (forces in a loss, stress
// derivatives), so double backward works too, and it is the same in eager mode and TorchScript.
// i, j, S and offsets are the integer outputs of the pair ops (int64) and get no gradient.
#include <cmath>
#include <cstdint>
#include <tuple>

#include <torch/csrc/autograd/custom_function.h>
#include <torch/library.h>
#include <torch/types.h>

#include "op_arguments.hpp"
#include "output_tensor.hpp"

namespace {

using namespace tricell::torch_ops; // op_arguments.hpp
using torch::autograd::AutogradContext;
using torch::autograd::variable_list;

constexpr const char* op = "pair_vectors";

void check_pairs(const at::Tensor& positions, const at::Tensor& cells, const at::Tensor& i,
                 const at::Tensor& j, const at::Tensor& S, const at::Tensor& offsets) {
    check_positions_and_cell(op, positions, cells, "cells");
    TORCH_CHECK(cells.dim() == 3 && cells.size(1) == 3 && cells.size(2) == 3, op,
                ": cells must be a B x 3 x 3 tensor (got shape ", shape_of(cells), ")");
    const auto pairs = i.size(0);
    for (const auto& [tensor, name] :
         {std::pair{i, "i"}, std::pair{j, "j"}, std::pair{S, "S"}, std::pair{offsets, "offsets"}}) {
        TORCH_CHECK(tensor.scalar_type() == at::kLong && tensor.device().is_cpu(), op, ": ", name,
                    " must be an int64 tensor on the CPU (got ", tensor.scalar_type(), " on ",
                    tensor.device(), ")");
    }
    TORCH_CHECK(i.dim() == 1 && j.dim() == 1 && j.size(0) == pairs && S.dim() == 2 &&
                    S.size(0) == pairs && S.size(1) == 3,
                op, ": i, j and S must have one row per pair (got shapes ", shape_of(i), ", ",
                shape_of(j), " and ", shape_of(S), ")");
    TORCH_CHECK(offsets.dim() == 1 && offsets.size(0) == cells.size(0) + 1, op,
                ": offsets must have one entry per cell and one more (got shape ",
                shape_of(offsets), " for ", cells.size(0), " cells)");
}

template <class Real>
void vectors_kernel(const at::Tensor& x, const at::Tensor& h, const at::Tensor& i,
                    const at::Tensor& j, const at::Tensor& S, const at::Tensor& offsets,
                    at::Tensor& out, at::Tensor& lengths) {
    const Real* xs = x.data_ptr<Real>();
    const Real* hs = h.data_ptr<Real>();
    const std::int64_t* is = i.data_ptr<std::int64_t>();
    const std::int64_t* js = j.data_ptr<std::int64_t>();
    const std::int64_t* ss = S.data_ptr<std::int64_t>();
    const std::int64_t* os = offsets.data_ptr<std::int64_t>();
    Real* d = out.data_ptr<Real>();
    Real* length = lengths.data_ptr<Real>();
    const std::int64_t atoms = x.size(0);
    const std::int64_t last = offsets.size(0) - 1;
    TORCH_CHECK(os[0] == 0 && os[last] == i.size(0), op,
                ": offsets must start at 0 and end at the number of pairs (got ", os[0], " and ",
                os[last], " for ", i.size(0), " pairs)");
    for (std::int64_t s = 0; s < last; ++s) {
        const Real* cell = hs + 9 * s;
        TORCH_CHECK(os[s] <= os[s + 1], op, ": offsets must not decrease (offsets[", s + 1,
                    "] = ", os[s + 1], " < offsets[", s, "] = ", os[s], ")");
        for (std::int64_t p = os[s]; p < os[s + 1]; ++p) {
            TORCH_CHECK(is[p] >= 0 && is[p] < atoms && js[p] >= 0 && js[p] < atoms, op, ": pair ",
                        p, " indexes an atom out of range (i = ", is[p], ", j = ", js[p], " for ",
                        atoms, " atoms)");
            const Real* a = xs + 3 * is[p];
            const Real* b = xs + 3 * js[p];
            const std::int64_t* shift = ss + 3 * p;
            for (int c = 0; c < 3; ++c) {
                const Real image = Real(shift[0]) * cell[c] + Real(shift[1]) * cell[3 + c] +
                                   Real(shift[2]) * cell[6 + c];
                d[3 * p + c] = b[c] - a[c] + image;
            }
            const Real* v = d + 3 * p;
            length[p] = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        }
    }
}

std::tuple<at::Tensor, at::Tensor>
pair_vectors_forward(const at::Tensor& positions, const at::Tensor& cells, const at::Tensor& i,
                     const at::Tensor& j, const at::Tensor& S, const at::Tensor& offsets) {
    check_pairs(positions, cells, i, j, S, offsets);
    const at::Tensor x = positions.contiguous();
    const at::Tensor h = cells.contiguous();
    const at::Tensor ic = i.contiguous(), jc = j.contiguous(), Sc = S.contiguous();
    const at::Tensor oc = offsets.contiguous();
    at::Tensor out = output_tensor({i.size(0), 3}, positions.scalar_type());
    at::Tensor lengths = output_tensor({i.size(0)}, positions.scalar_type());
    if (positions.scalar_type() == at::kDouble) {
        vectors_kernel<double>(x, h, ic, jc, Sc, oc, out, lengths);
    } else {
        vectors_kernel<float>(x, h, ic, jc, Sc, oc, out, lengths);
    }
    return {out, lengths};
}

class PairVectors : public torch::autograd::Function<PairVectors> {
  public:
    static variable_list forward(AutogradContext* ctx, const at::Tensor& positions,
                                 const at::Tensor& cells, const at::Tensor& i, const at::Tensor& j,
                                 const at::Tensor& S, const at::Tensor& offsets) {
        ctx->saved_data["atoms"] = positions.size(0);
        ctx->saved_data["cells"] = cells.size(0);
        at::Tensor vectors, lengths;
        {
            at::AutoDispatchBelowADInplaceOrView guard;
            std::tie(vectors, lengths) =
                pair_vectors_forward(positions.detach(), cells.detach(), i, j, S, offsets);
        }
        ctx->save_for_backward({i, j, S, offsets, vectors, lengths});
        return {vectors, lengths};
    }

    static variable_list backward(AutogradContext* ctx, variable_list grads) {
        const auto saved = ctx->get_saved_variables();
        const at::Tensor &i = saved[0], &j = saved[1], &S = saved[2], &offsets = saved[3];
        const at::Tensor &vectors = saved[4], &lengths = saved[5];
        at::Tensor g = grads[0].defined() ? grads[0] : at::zeros_like(vectors);
        if (grads[1].defined()) { // d's share: g_d D / d, nothing where d = 0
            const at::Tensor positive = lengths > 0;
            const at::Tensor safe = at::where(positive, lengths, at::ones_like(lengths));
            const at::Tensor scale = at::where(positive, grads[1] / safe, at::zeros_like(lengths));
            g = g + scale.unsqueeze(1) * vectors;
        }
        const auto atoms = ctx->saved_data["atoms"].toInt();
        const auto cells = ctx->saved_data["cells"].toInt();
        at::Tensor grad_positions =
            at::zeros({atoms, 3}, g.options()).index_add(0, j, g).index_add(0, i, -g);
        const at::Tensor system =
            at::repeat_interleave(at::arange(cells, offsets.options()), offsets.diff());
        at::Tensor grad_cells =
            at::zeros({cells, 3, 3}, g.options())
                .index_add(0, system, S.to(g.scalar_type()).unsqueeze(2) * g.unsqueeze(1));
        return {grad_positions, grad_cells, at::Tensor(), at::Tensor(), at::Tensor(), at::Tensor()};
    }
};

std::tuple<at::Tensor, at::Tensor>
pair_vectors_autograd(const at::Tensor& positions, const at::Tensor& cells, const at::Tensor& i,
                      const at::Tensor& j, const at::Tensor& S, const at::Tensor& offsets) {
    const variable_list out = PairVectors::apply(positions, cells, i, j, S, offsets);
    return {out[0], out[1]};
}

} // namespace

TORCH_LIBRARY_FRAGMENT(tricell, m) {
    m.def("pair_vectors(Tensor positions, Tensor cells, Tensor i, Tensor j, Tensor S, "
          "Tensor offsets) -> (Tensor D, Tensor d)");
}

TORCH_LIBRARY_IMPL(tricell, CPU, m) {
    m.impl("pair_vectors", &pair_vectors_forward);
}

TORCH_LIBRARY_IMPL(tricell, Autograd, m) {
    m.impl("pair_vectors", &pair_vectors_autograd);
}
