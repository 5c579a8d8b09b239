"""The samplers' own rotation conversions agree with scipy's at every angle, half turns and
no turn included (they replace it on the planner's hot paths)."""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from pdsketch_mech.samplers.geometry import matrix_pose, matrix_quaternion, rotation_between, rotvec_matrices

SPECIAL = [np.zeros(3), np.array([np.pi, 0, 0]), np.array([0, np.pi, 0]), np.array([0, 0, np.pi]),
           np.array([1, 1, 0]) / np.sqrt(2) * np.pi, np.array([0, np.pi - 1e-9, 0]), np.array([1e-14, 0, 0])]


def same_rotation(q1, q2) -> bool:
    return abs(abs(float(np.dot(q1, q2))) - 1.0) < 1e-12


@pytest.mark.parametrize("rotvec", SPECIAL + list(np.random.default_rng(0).normal(size=(50, 3)) * 2))
def test_a_matrix_becomes_the_quaternion_scipy_gives_with_w_not_negative(rotvec):
    matrix = Rotation.from_rotvec(rotvec).as_matrix()
    quaternion = matrix_quaternion(matrix)
    assert same_rotation(quaternion, Rotation.from_matrix(matrix).as_quat())
    assert quaternion[3] >= 0 and abs(np.linalg.norm(quaternion) - 1.0) < 1e-12


def test_rotation_vectors_become_scipys_matrices_one_at_a_time_and_in_batches():
    batch = np.concatenate([np.array(SPECIAL), np.random.default_rng(1).normal(size=(201, 3)) * 3])   # 208 rows
    expected = Rotation.from_rotvec(batch).as_matrix()
    assert np.allclose(rotvec_matrices(batch), expected, atol=1e-12)
    assert np.allclose(rotvec_matrices(batch.reshape(2, -1, 3)), expected.reshape(2, -1, 3, 3), atol=1e-12)
    for rotvec, matrix in zip(batch, expected):
        assert np.allclose(rotvec_matrices(rotvec), matrix, atol=1e-12)


@pytest.mark.parametrize("a, b", [((0, 0, 1), (0, 0, 1)), ((0, 0, 1), (0, 0, -1)), ((1, 0, 0), (0, 1, 0)),
                                  ((0.6, 0, 0.8), (-0.6, 0, -0.8))])
def test_rotation_between_takes_a_onto_b(a, b):
    a, b = np.array(a, dtype=float), np.array(b, dtype=float)
    rotation = rotation_between(a, b)
    assert np.allclose(rotation @ a, b, atol=1e-12) and np.allclose(rotation @ rotation.T, np.eye(3), atol=1e-12)


def test_a_transform_becomes_its_pose():
    matrix = np.eye(4)
    matrix[:3, :3], matrix[:3, 3] = Rotation.from_rotvec([0.3, -1.2, 2.0]).as_matrix(), (0.1, -0.2, 0.3)
    position, quaternion = matrix_pose(matrix)
    assert position == (0.1, -0.2, 0.3) and same_rotation(quaternion, Rotation.from_matrix(matrix[:3, :3]).as_quat())
