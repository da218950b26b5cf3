"""Large mechanisms: the block structure of DΦ, loop-by-loop D²Φ, memory that grows with the loops.

The block path (:data:`manifold.implicit.BLOCK_THRESHOLD` lowered to 0) must
agree with the dense one on small mechanisms: the same singular values and
rank decisions, the same kernel and row space, the same projections and
curvatures. A ladder of 100 planar four-bar loops (400 joints) and a file of
thousands of pendulums must work within memory bounds checked with
tracemalloc (no c×k×k or k×k×c array), and a mechanism whose tangent bases
alone exceed the limit is refused naming the field.
"""

import numpy as np
import pytest

from builders import (bennett, five_bar, five_bar_positions, ladder, rsur, spatial_mix, spherical_four_bar,
                      traced_peak)
from manifold import AmbientSpace, ImplicitManifold, ProjectionError, numerical_rank, project, tangent_basis
from manifold import implicit
from manifold.implicit import (
    STALL_WINDOW, JacobianPattern, constraint_curvature, hessian_form, jacobian_rank, normal_basis,
    sparse_tangent_basis,
)
from mechanisms import (
    Joint, Mechanism, MechanismError, configuration_space, constraint, constraint_hessian,
    constraint_jacobian, home, kinematics_of,
)
from mechanisms.catalogue.slider_crank import slider_crank
from mechanisms.kinematics import constraint_hessian_form, constraint_jacobian_entries, constraint_pattern
from mechanisms.mechanism import DENSE_MEMORY_LIMIT, dense_memory_estimate


def pendulums(count):
    """`count` pendulums hung from the ground: no loop, k = count."""
    return Mechanism("pendulums", "planar", [Joint(f"P{index}", "R", ("ground", f"pendulum{index}"),
                                                   point=(float(index), 0.0)) for index in range(count)])


SMALL = {
    "slider-crank": lambda: slider_crank(crank=2.0, coupler=1.0, theta=0.3),
    "five-bar": lambda: five_bar(five_bar_positions(1.2, 2.0)),
    "spherical four-bar": spherical_four_bar,
    "bennett": bennett,
    "RSUR": rsur,
    "mix": spatial_mix,
    "ladder of 3": lambda: ladder(3),
}

LADDER = ladder(100)


def projector(basis, scales):
    """Orthogonal projector onto the span of a basis in dimensionless coordinates."""
    unit = np.linalg.qr(basis / scales[:, None])[0] if basis.shape[1] else basis
    return unit @ unit.T


@pytest.fixture
def blocks(monkeypatch):
    """Every manifold with a pattern handled block by block, whatever its size."""
    monkeypatch.setattr(implicit, "BLOCK_THRESHOLD", 0)


def near_points(mechanism, rng, count=2):
    """Points of M near the home (and the home itself)."""
    manifold = configuration_space(mechanism)
    space = manifold.ambient
    starts = space.retract(home(mechanism), 0.05 * rng.standard_normal((count, space.dim)))
    return [home(mechanism)] + [project(manifold, start) for start in starts]


# ------------------------------------------------------------------ the pattern of DΦ

@pytest.mark.parametrize("name", sorted(SMALL))
def test_pattern_entries_are_dense_jacobian_and_hold_every_nonzero(name):
    rng = np.random.default_rng(20)
    mechanism = SMALL[name]()
    pattern = constraint_pattern(mechanism)
    points = kinematics_of(mechanism).ambient.random_point(rng, size=4).reshape(2, 2, -1)
    dense = constraint_jacobian(mechanism, points)
    entries = constraint_jacobian_entries(mechanism, points)
    assert entries.shape == (2, 2, pattern.nnz)
    np.testing.assert_array_equal(dense[..., pattern.rows, pattern.columns], entries)
    outside = np.ones(pattern.shape, dtype=bool)
    outside[pattern.rows, pattern.columns] = False
    assert not np.any(dense[..., outside])
    assert len(set(zip(pattern.rows.tolist(), pattern.columns.tolist()))) == pattern.nnz


def test_ladder_loops_are_separate_blocks_of_three_rows_by_four_columns():
    pattern = constraint_pattern(LADDER)
    assert pattern.shape == (300, 400) and pattern.nnz == 1200
    (group,) = pattern.blocks
    assert group.rows.shape == (100, 3) and group.columns.shape == (100, 4)
    assert not len(pattern.free_columns)
    assert sorted(group.columns.ravel().tolist()) == list(range(400))


def test_blocks_of_a_pattern_with_an_empty_row_and_free_columns():
    pattern = JacobianPattern((5, 6), rows=[0, 0, 1, 2, 3, 3], columns=[4, 0, 0, 2, 2, 5])
    (group,) = pattern.blocks  # two 2×2 blocks, evaluated together; row 4 touches nothing
    assert sorted(map(tuple, group.rows.tolist())) == [(0, 1), (2, 3)]
    assert sorted(map(tuple, group.columns.tolist())) == [(0, 4), (2, 5)]
    assert pattern.free_columns.tolist() == [1, 3]
    entries = np.arange(1.0, 7.0)
    dense = np.zeros((5, 6))
    dense[pattern.rows, pattern.columns] = entries
    padded = np.append(entries, 0.0)
    for rows, columns, positions in zip(group.rows, group.columns, group.positions):
        np.testing.assert_array_equal(dense[np.ix_(rows, columns)], padded[positions])


# ------------------------------------------------------------------ block path = dense path

def random_block_manifold(rng):
    """Φ(x) = A x + 0.1 (A x)² (entrywise) in ℝ⁹, A with blocks of two shapes, a tall block, an empty row
    and a free column; DΦ has A's pattern and D²Φ_i = 0.2 A_iᵀ A_i."""
    matrix = np.zeros((8, 9))
    matrix[np.ix_([0, 1], [0, 3, 5])] = rng.standard_normal((2, 3))
    matrix[np.ix_([2, 4], [1, 2, 8])] = rng.standard_normal((2, 3))
    matrix[np.ix_([5, 6, 7], [4, 6])] = rng.standard_normal((3, 2))  # tall: more rows than columns
    rows, columns = np.nonzero(matrix)  # row 3 empty, column 7 free

    def constraint(x):
        linear = x @ matrix.T
        return linear + 0.1 * linear ** 2

    def jacobian(x):
        return (1.0 + 0.2 * (x @ matrix.T))[..., :, None] * matrix

    def hessian(x):
        return 0.2 * np.einsum("ia,ib->iab", matrix, matrix) * np.ones(np.shape(x)[:-1] + (1, 1, 1))

    scales = tuple(rng.uniform(0.5, 2.0, 9))
    return ImplicitManifold(AmbientSpace(("R",) * 9, scales), constraint, jacobian, hessian,
                            pattern=JacobianPattern((8, 9), rows, columns),
                            constraint_jacobian_entries=lambda x: jacobian(x)[..., rows, columns])


def dense_twin(manifold):
    """The same manifold without its pattern (always dense)."""
    return ImplicitManifold(manifold.ambient, manifold.constraint, manifold.constraint_jacobian,
                            manifold.constraint_hessian, manifold.is_solution)


def assert_block_path_matches_dense(manifold, point, rng):
    dense = dense_twin(manifold)
    scales = manifold.ambient.tangent_scales
    blocked, reference = jacobian_rank(manifold, point), numerical_rank(implicit.scaled_jacobian(dense, point))
    assert blocked.rank == reference.rank and blocked.tolerance == pytest.approx(reference.tolerance, rel=1e-12)
    np.testing.assert_allclose(blocked.singular_values, reference.singular_values, atol=1e-12)
    basis, decision = tangent_basis(manifold, point)
    dense_basis, _ = tangent_basis(dense, point)
    assert decision.rank == reference.rank and basis.shape == dense_basis.shape
    np.testing.assert_allclose((basis / scales[:, None]).T @ (basis / scales[:, None]), np.eye(basis.shape[1]),
                               atol=1e-12)
    np.testing.assert_allclose(projector(basis, scales), projector(dense_basis, scales), atol=1e-10)
    np.testing.assert_allclose(sparse_tangent_basis(manifold, point)[0].toarray(), basis, atol=1e-15)
    normal = normal_basis(manifold, point)
    np.testing.assert_allclose(normal @ normal.T, projector(normal_basis(dense, point), np.ones(len(scales))),
                               atol=1e-10)
    np.testing.assert_allclose(constraint_curvature(manifold, point, basis),
                               constraint_curvature(dense, point, basis), atol=1e-10)
    start = manifold.ambient.retract(point, 0.02 * scales * rng.standard_normal(len(scales)))
    projected, dense_projected = project(manifold, start), project(dense, start)
    if reference.rank == len(reference.singular_values):
        np.testing.assert_allclose(projected, dense_projected, atol=1e-10)
    else:  # redundant rows: off M, DΦ has a singular value of the order of |Φ|, which amplifies rounding,
        # and the iterations reach M at nearby points of the same fibre
        for found in (projected, dense_projected):
            assert np.linalg.norm(manifold.constraint(found)) <= 1e-12
        assert np.linalg.norm(projected - dense_projected) < 1e-3 * np.linalg.norm(start - dense_projected)


@pytest.mark.parametrize("name", sorted(SMALL))
def test_block_path_matches_the_dense_path_on_small_mechanisms(name, blocks):
    rng = np.random.default_rng(21)
    mechanism = SMALL[name]()
    manifold = configuration_space(mechanism)
    for point in near_points(mechanism, rng):
        assert_block_path_matches_dense(manifold, point, rng)


def test_block_path_matches_the_dense_path_with_tall_blocks_empty_rows_and_free_columns(blocks):
    rng = np.random.default_rng(22)
    manifold = random_block_manifold(rng)
    for _ in range(3):
        point = project(dense_twin(manifold), rng.standard_normal(9))
        assert_block_path_matches_dense(manifold, point, rng)


def test_rank_of_a_singular_block_is_decided_against_the_largest_singular_value_of_the_whole(blocks):
    rng = np.random.default_rng(23)
    manifold = random_block_manifold(rng)
    point = np.zeros(9)
    values = jacobian_rank(manifold, point).singular_values
    assert len(values) == 8 and np.all(np.diff(values) <= 0) and values[-1] == 0.0  # the empty row
    assert jacobian_rank(manifold, point).tolerance == pytest.approx(1e-6 * values[0])


def test_sparse_solves_of_large_blocks_still_project_onto_the_manifold(blocks, monkeypatch):
    monkeypatch.setattr(implicit, "SPARSE_BLOCK_COLUMNS", 2)
    rng = np.random.default_rng(24)
    manifold = random_block_manifold(rng)
    point = project(manifold, 0.1 * rng.standard_normal(9))
    assert np.linalg.norm(manifold.constraint(point)) <= 1e-12


# ------------------------------------------------------------------ second derivatives loop by loop

@pytest.mark.parametrize("name", sorted(SMALL))
def test_hessian_form_equals_the_contracted_dense_hessian(name):
    rng = np.random.default_rng(25)
    mechanism = SMALL[name]()
    space = kinematics_of(mechanism).ambient
    points = space.random_point(rng, size=2)
    left, right = rng.standard_normal((space.dim, 3)), rng.standard_normal((space.dim, 2))
    expected = np.einsum("...cab,ai,bj->...cij", constraint_hessian(mechanism, points), left, right)
    np.testing.assert_allclose(constraint_hessian_form(mechanism, points, left, right), expected, atol=1e-12)
    np.testing.assert_allclose(hessian_form(configuration_space(mechanism), points[0], left, right), expected[0],
                               atol=1e-12)


def test_hessian_form_of_the_ladder_passes_the_taylor_test():
    rng = np.random.default_rng(26)
    space = kinematics_of(LADDER).ambient
    point = space.random_point(rng)
    direction = rng.standard_normal(space.dim)
    value, first = constraint(LADDER, point), constraint_jacobian(LADDER, point) @ direction
    second = constraint_hessian_form(LADDER, point, direction[:, None])[:, 0, 0]
    steps = np.array([1e-2, 5e-3, 2.5e-3])
    errors = [np.linalg.norm(constraint(LADDER, space.retract(point, step * direction)) - value - step * first
                             - 0.5 * step ** 2 * second) for step in steps]
    assert np.polyfit(np.log(steps), np.log(errors), 1)[0] > 2.9


# ------------------------------------------------------------------ a ladder of 400 joints

def test_ladder_of_four_hundred_joints_is_well_within_the_memory_limit():
    assert (len(LADDER.joints), LADDER.loop_count, LADDER.ambient_dimension) == (400, 100, 400)
    assert LADDER.dense_memory_estimate == dense_memory_estimate(400, 300) == 8 * (300 * 400 + 4 * 400 * 100)


def test_ladder_jacobian_rank_basis_and_projection_stay_within_a_few_megabytes():
    manifold = configuration_space(LADDER)
    point = home(LADDER)
    decision, peak = traced_peak(jacobian_rank, manifold, point)
    assert decision.rank == 300 and peak < 2 * 2 ** 20
    (basis, _), peak = traced_peak(tangent_basis, manifold, point)
    assert basis.shape == (400, 100) and peak < 4 * 2 ** 20  # the basis itself is 0.3 MB
    rng = np.random.default_rng(27)
    start = manifold.ambient.retract(point, 0.01 * rng.standard_normal(400))
    projected, peak = traced_peak(project, manifold, start)
    assert np.linalg.norm(constraint(LADDER, projected)) <= 1e-12 and peak < 4 * 2 ** 20


def test_sparse_tangent_basis_of_the_ladder_has_one_column_of_four_entries_per_loop():
    manifold = configuration_space(LADDER)
    sparse, decision = sparse_tangent_basis(manifold, home(LADDER))
    dense, dense_decision = tangent_basis(manifold, home(LADDER))
    assert sparse.shape == (400, 100) and sparse.nnz == 400 and decision.rank == dense_decision.rank == 300
    np.testing.assert_array_equal(sparse.toarray(), dense)


def test_ladder_curvature_needs_no_dense_hessian():
    manifold = configuration_space(LADDER)
    point = home(LADDER)
    basis = tangent_basis(manifold, point)[0][:, :6]
    acceleration, peak = traced_peak(constraint_curvature, manifold, point, basis)
    assert acceleration.shape == (400, 6, 6)
    assert peak < 8 * 2 ** 20  # the dense D²Φ alone would be 300 × 400 × 400 floats: 384 MB
    # on M the curvature solves DΦ x'' = −D²Φ(b_i, b_j)
    second = hessian_form(manifold, point, basis)
    np.testing.assert_allclose(np.einsum("ck,kij->cij", constraint_jacobian(LADDER, point), acceleration),
                               -second, atol=1e-10)
    np.testing.assert_allclose(constraint_curvature(manifold, point, basis[:, :2], right=basis), acceleration[:, :2],
                               atol=1e-15)


def test_projection_on_the_ladder_gives_up_early_when_it_stalls():
    """Block by block, Gauss-Newton stops once the residual fell by less than 1 % over STALL_WINDOW iterations,
    not at max_iterations (60): from a random start with steps capped at 1e-3, no progress is possible. (Each
    loop's rows are written about its own rung, mechanisms.kinematics.loop_origin: with every loop about the
    ground, 100 rungs up, Gauss-Newton stalled from a random start even with steps of 1.)"""
    manifold = configuration_space(LADDER)
    rng = np.random.default_rng(28)
    start = manifold.ambient.random_point(rng, center=home(LADDER))
    with pytest.raises(ProjectionError, match=r"after (\d+) iterations") as caught:
        project(manifold, start, max_step=1e-3)
    assert int(caught.value.args[0].rsplit("after ", 1)[1].split()[0]) == STALL_WINDOW


# ------------------------------------------------------------------ many pendulums

def test_many_pendulums_are_accepted_and_need_no_k_by_k_by_c_array():
    k = 1000
    mechanism = pendulums(k)
    manifold = configuration_space(mechanism)
    point = home(mechanism)
    decision, peak = traced_peak(jacobian_rank, manifold, point)
    assert decision.rank == 0 and peak < 2 ** 20
    (basis, _), peak = traced_peak(tangent_basis, manifold, point)
    np.testing.assert_array_equal(basis, np.eye(k))
    assert peak <= 8 * k * k + 2 ** 20  # the k × k basis itself, nothing beside it
    form, peak = traced_peak(constraint_hessian_form, mechanism, point, np.eye(k)[:, :3])
    assert form.shape == (0, 3, 3) and peak < 2 ** 20
    hessian, peak = traced_peak(constraint_hessian, mechanism, point)
    assert hessian.shape == (0, k, k) and peak < 2 ** 20


def test_pendulums_whose_tangent_bases_exceed_the_limit_are_refused_naming_the_field():
    count = 6000  # 4 bases of 6000 × 6000 floats: more than 1 GiB (5792 pendulums would be accepted)
    assert dense_memory_estimate(5792, 0) <= DENSE_MEMORY_LIMIT < dense_memory_estimate(count, 0)
    with pytest.raises(MechanismError) as caught:
        pendulums(count)
    message = str(caught.value)
    assert message.startswith("field 'joints': the mechanism is too large for the dense algorithms: 6000 joint "
                              "coordinates and 0 constraint rows need at least 1.07 GiB")
    assert "\n" not in message
