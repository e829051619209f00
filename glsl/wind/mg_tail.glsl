// Multigrid, the V-cycle's tail in one workgroup: from level pc.mg_level
// (its right-hand side restricted, its correction zero, or level 0's
// pressure as it stands) down through every coarser level to the coarsest
// (pc.coarsest_sweeps red-black sweeps) and back up to pc.mg_level, the
// same kernels' arithmetic (`Multigrid::v_cycle`) on a copy of those
// levels in shared memory, with a workgroup barrier where the kernels
// would each need a dispatch. A GPU pays its dispatch-and-drain latency
// per dependent dispatch, and the coarse levels are small: on table1's
// grid 23 of a V-cycle's 45 dispatches were for levels of at most 1,125
// cells. The host picks pc.mg_level as the finest level whose pressure,
// right-hand side, residual and face conductances
// (`Multigrid::tail_footprint`) fit TAIL_CAPACITY floats.
#define WIND_KERNEL_GROUP MG_TAIL_GROUP
#include "wind_kernel.glsl"

// The coarsest level's number, specialised at pipeline creation
// (src/compute/wind_pass/). The shared array's size, TAIL_CAPACITY, is
// the including kernel's: mg_tail.comp fits the 16 KiB every device
// offers, mg_tail_large.comp 48 KiB.
layout(constant_id = 0) const uint MG_LAST_LEVEL = 0u;
// Each tail level's pressure, then each one's right-hand side, then one
// residual scratch the size of the tail's finest level (each level's
// residual is restricted before the next is computed), then the tail
// levels' face conductances: everything a sweep reads is here, since one
// workgroup has few warps to hide a memory access behind.
shared float tail[TAIL_CAPACITY];
// The level table, and where each tail level's pressure starts in `tail`
// (its right-hand side starts tail_cells later).
shared MgLevel tail_levels[MG_MAX_LEVELS];
shared uint tail_base[MG_MAX_LEVELS];
shared uint tail_cells;
// Where the conductances start in `tail`, less the index of the tail's
// first conductance in the conductance buffer.
shared uint tail_k;

#define MG_LEVELS tail_levels
#define MG_CONDUCTANCE(index) tail[tail_k + (index)]
#define MG_P(l, index) tail[tail_base[l] + (index)]
#define MG_B(l, index) tail[tail_cells + tail_base[l] + (index)]
#define MG_SAVED_RESIDUAL(index) tail[2u * tail_cells + (index)]
#include "multigrid.glsl"

// One thread's cell of one colour on a level with at most one such cell
// per thread, its stencil held in registers through every sweep: the
// coarsest level's 40 sweeps are each a barrier apart, so the time a
// sweep takes is the time one cell takes.
struct TailCell {
    bool present;
    uint index;
    float diagonal;
    float b;
    float k[6];
    uint nb[6];
};

TailCell tail_cell(uint l, uint color) {
    TailCell t;
    uvec3 c;
    t.present = gl_LocalInvocationID.x < mg_color_cell_count(l)
        && mg_cell_of_color(l, gl_LocalInvocationID.x, color, c);
    if (!t.present) {
        return t;
    }
    bool inside[6];
    mg_stencil_terms(l, c, t.k, t.nb, inside);
    t.index = mg_cell_index(l, c);
    t.diagonal = 0.0;
    for (uint j = 0u; j < 6u; j += 2u) {
        t.diagonal += t.k[j] + t.k[j + 1u];
    }
    for (uint j = 0u; j < 6u; ++j) {
        // A neighbour beyond the grid adds nothing (`mg_stencil`).
        t.k[j] = inside[j] ? t.k[j] : 0.0;
        t.nb[j] = inside[j] ? t.nb[j] : t.index;
    }
    t.b = MG_B(l, t.index);
    return t;
}

void tail_update(TailCell t, uint l) {
    if (!t.present) {
        return;
    }
    float neighbours = 0.0;
    for (uint j = 0u; j < 6u; ++j) {
        neighbours += t.k[j] * MG_P(l, t.nb[j]);
    }
    MG_P(l, t.index) = t.diagonal == 0.0 ? 0.0 : (t.b + neighbours) / t.diagonal;
}

// Both colours of one level, `sweeps` times, a barrier after each.
void tail_smooth(uint l, uint sweeps) {
    uint n = mg_color_cell_count(l);
    if (n <= MG_TAIL_GROUP) {
        TailCell red = tail_cell(l, 0u);
        TailCell black = tail_cell(l, 1u);
        for (uint sweep = 0u; sweep < sweeps; ++sweep) {
            tail_update(red, l);
            barrier();
            tail_update(black, l);
            barrier();
        }
        return;
    }
    for (uint sweep = 0u; sweep < sweeps; ++sweep) {
        for (uint color = 0u; color < 2u; ++color) {
            for (uint i = gl_LocalInvocationID.x; i < n; i += MG_TAIL_GROUP) {
                uvec3 c;
                if (mg_cell_of_color(l, i, color, c)) {
                    MG_P(l, mg_cell_index(l, c)) = mg_smoothed(l, c);
                }
            }
            barrier();
        }
    }
}

void main() {
    uint first = pc.mg_level;
    uint last = MG_LAST_LEVEL;
    uint lane = gl_LocalInvocationID.x;
    for (uint l = lane; l <= last; l += MG_TAIL_GROUP) {
        tail_levels[l] = levels[l];
    }
    barrier();
    uint n_first = mg_cell_count(first);
    // The tail levels' conductances: a suffix of the buffer (level by
    // level, axis by axis).
    uint k_first = tail_levels[first].conductance.x;
    if (lane == 0u) {
        uint at = 0u;
        for (uint l = first; l <= last; ++l) {
            tail_base[l] = at;
            at += mg_cell_count(l);
        }
        tail_cells = at;
        tail_k = 2u * at + n_first - k_first;
    }
    barrier();
    uvec3 n_last = tail_levels[last].cells;
    uint k_end = tail_levels[last].conductance.z + n_last.x * n_last.y * (n_last.z + 1u);
    for (uint i = k_first + lane; i < k_end; i += MG_TAIL_GROUP) {
        MG_CONDUCTANCE(i) = conductance[i];
    }
    for (uint i = lane; i < n_first; i += MG_TAIL_GROUP) {
        MG_P(first, i) = mg_p(first, i);
        MG_B(first, i) = mg_b(first, i);
    }
    barrier();
    for (uint l = first; l < last; ++l) {
        tail_smooth(l, MG_PRE_SMOOTH);
        uint n = mg_cell_count(l);
        for (uint i = lane; i < n; i += MG_TAIL_GROUP) {
            MG_SAVED_RESIDUAL(i) = mg_residual(l, i);
        }
        barrier();
        uint n_coarse = mg_cell_count(l + 1u);
        for (uint i = lane; i < n_coarse; i += MG_TAIL_GROUP) {
            MG_B(l + 1u, i) = mg_restricted(l, i);
            MG_P(l + 1u, i) = 0.0;
        }
        barrier();
    }
    tail_smooth(last, pc.coarsest_sweeps);
    for (uint l = last; l > first; --l) {
        uint fine = l - 1u;
        uint n = mg_cell_count(fine);
        for (uint i = lane; i < n; i += MG_TAIL_GROUP) {
            MG_P(fine, i) += mg_prolonged(fine, i);
        }
        barrier();
        tail_smooth(fine, MG_POST_SMOOTH);
    }
    for (uint i = lane; i < n_first; i += MG_TAIL_GROUP) {
        mg_set_p(first, i, MG_P(first, i));
    }
}
