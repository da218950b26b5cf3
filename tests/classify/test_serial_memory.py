"""Memory of a long serial chain: nothing of the end-effector reference grows with k².

The reference scale of the end-effector rank decision
(:func:`mechanisms.kinematics.end_effector_reference`) needs the pose of every
link carrying an axis. Each link's chain from the ground holds its depth in
elements, so the chains of a serial chain of k joints hold k(k + 1)/2 of them:
written out as chain groups (twists, squares, columns: some 240 bytes an
element) they took more than 6 GB at k = 5000, before any k × k array, past a
size check that allows 1 GiB. The prefix tree is grown link by link along the
spanning tree instead (:func:`mechanisms._chains.prefix_tree`): a node per joint.
"""

import numpy as np

from builders import traced_peak
from mechanisms import EndEffector, Joint, Mechanism, home, kinematics_of
from mechanisms import _chains as chains
from mechanisms.kinematics import _reference_plan, end_effector_jacobian, end_effector_reference


def serial_chain(count, space="planar"):
    """`count` revolute joints in a row from the ground, the last link's point (planar) or pose (spatial) the
    end-effector: no loop, k = count."""
    links = ["ground"] + [f"link{index}" for index in range(count)]
    if space == "planar":
        joints = [Joint(f"J{index}", "R", (links[index], links[index + 1]), point=(0.01 * index, 0.0))
                  for index in range(count)]
        return Mechanism(f"serial {count}", space, joints,
                         end_effector=EndEffector(links[-1], (0.01 * count, 0.0), "position"))
    joints = [Joint(f"J{index}", "R", (links[index], links[index + 1]), point=(0.01 * index, 0.0, 0.0),
                    axis=(0.0, np.sin(index), np.cos(index))) for index in range(count)]
    return Mechanism(f"serial {count}", space, joints,
                     end_effector=EndEffector(links[-1], (0.01 * count, 0.0, 0.0), "pose"))


def test_the_reference_plan_of_a_long_planar_serial_chain_is_linear_in_its_joints():
    """k = 1000: the chains to the links hold 500,500 elements (some 120 MB as chain groups); the plan's prefix
    tree has a node per joint and its construction stays within 4 MB."""
    count = 1000
    mechanism = serial_chain(count)
    kinematics_of(mechanism)
    plan, peak = traced_peak(_reference_plan, mechanism)
    assert len(plan.tree.parents) <= count + 1
    assert peak < 4 * 2 ** 20


def test_the_reference_plan_of_a_spatial_serial_chain_writes_out_no_chain(monkeypatch):
    """The matrix form of the tree (spatial and spherical mechanisms) at k = 600: the chains to the links hold
    180,300 elements, the spanning tree 600; no more than those are ever written out (each as it is reached),
    and the plan's tree has a node per joint."""
    count = 600
    mechanism = serial_chain(count, "spatial")
    kinematics_of(mechanism)
    written, traverse = [], chains.traverse
    monkeypatch.setattr(chains, "traverse", lambda *arguments: written.append(traverse(*arguments)) or written[-1])
    plan = _reference_plan(mechanism)
    assert len(plan.tree.parents) <= count + 1
    assert sum(len(chain.elements) for chain in written) <= 2 * count


def test_the_serial_chain_reference_is_dfs_columns_on_its_path():
    """On a serial chain every joint is on the path to the end-effector: the reference (its columns up to an
    orthogonal change) has Df's singular values, from the prefix tree built link by link."""
    for space in ("planar", "spatial"):
        mechanism = serial_chain(30, space)
        ambient = kinematics_of(mechanism).ambient
        point = ambient.retract(home(mechanism), np.random.default_rng(45).standard_normal(30) * 0.3)
        scales = ambient.tangent_scales
        expected = np.linalg.svd(end_effector_jacobian(mechanism, point) * scales, compute_uv=False)
        actual = np.linalg.svd(end_effector_reference(mechanism, point), compute_uv=False)
        np.testing.assert_allclose(actual[:len(expected)], expected, rtol=1e-12, atol=1e-12 * expected[0])


def test_the_prefix_tree_shares_every_prefix():
    """prefix_tree: a node per element on the paths to the links asked for, each link's node at its depth."""
    mechanism = serial_chain(50)
    link_chains = kinematics_of(mechanism).link_chains
    links = ["link49", "link9", "link0"]
    parents, last, ends, lengths = chains.prefix_tree(link_chains, links)
    assert len(parents) == 51 and len(last) == 50
    np.testing.assert_array_equal(lengths, [50, 10, 1])
    np.testing.assert_array_equal(lengths, [len(link_chains[link].elements) for link in links])
    np.testing.assert_array_equal(ends, [50, 10, 1])

