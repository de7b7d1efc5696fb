"""Vision and robot bindings: the simulator's images as RGB arrays, a push recorded and read back
as arrays, its segmentation, cameras, vocabularies; bad arrays are ValueErrors naming them."""

import numpy as np
import pytest

from proprio.episode import Episode
from proprio.features import (ExtractOptions, KmeansOptions, Vocabulary, build_vocabulary,
                              extract_features)
from proprio.geometry import Camera
from proprio.segmentation import MlOptions, segment_ml
from proprio.sim import Scene, SimulatedRobot, TableOptions

W, H = 160, 120


@pytest.fixture(scope="module")
def pushed(tmp_path_factory):
    """A simulated robot at 160 x 120 and one push recorded as an episode (seed 4: the first object,
    the book, lies where a 10 cm run-up along +x stays clear of the arm's base)."""
    robot = SimulatedRobot(TableOptions(objects=2, seed=4, width=W, height=H))
    target = robot.ground_truth()[0]["centre"]
    path = tmp_path_factory.mktemp("push") / "episode"
    report = robot.push(target[:2] - [0.1, 0.0], target[:2] + [0.05, 0.0], episode_dir=path)
    yield robot, report, path
    robot.close()


def test_scene_renders_rgb_mask_and_depth():
    with Scene([("mug", 0.3, 0.0)], width=W, height=H) as scene:
        frame = scene.render(depth=True)
        rgb, mask, depth = frame["rgb"], frame["mask"], frame["depth"]
        assert rgb.shape == (H, W, 3) and rgb.dtype == np.uint8 and rgb.flags.c_contiguous
        assert mask.shape == (H, W) and mask.dtype == np.uint16
        assert depth.shape == (H, W) and depth.dtype == np.float32
        assert scene.object_names == ["mug"]
        assert 1 in np.unique(mask)  # the mug is in view
        assert np.all(depth[mask == 1] > 0.3)  # metres from a camera 0.8 m away
        # The camera sees the mug where its pose projects.
        camera = scene.camera()
        pose = scene.object_pose("mug")
        u, v = camera.project(np.ascontiguousarray(pose[None, :3, 3]))[0]
        ys, xs = np.nonzero(mask == 1)
        assert xs.min() - 3 <= u <= xs.max() + 3 and ys.min() - 10 <= v <= ys.max() + 3
        t0 = scene.time
        scene.step(10)
        assert np.isclose(scene.time - t0, 10 * scene.timestep)


def test_camera_matrices():
    K = np.array([[500.0, 0, 320], [0, 500, 240], [0, 0, 1]])
    cam = Camera(K, np.eye(3), np.array([0.0, 0, 1]), 640, 480)
    np.testing.assert_allclose(cam.P(), K @ np.hstack([np.eye(3), [[0], [0], [1]]]))
    np.testing.assert_allclose(cam.project(np.array([[0.0, 0, 1]])), [[320, 240]])
    np.testing.assert_allclose(cam.center(), [0, 0, -1])
    with pytest.raises(ValueError, match="K"):
        Camera(np.eye(2), np.eye(3), np.zeros(3))
    with pytest.raises(ValueError, match="t: expected size 3"):
        Camera(K, np.eye(3), np.zeros(4))


def test_robot_look_and_push(pushed):
    robot, report, path = pushed
    look = robot.look()
    assert look["image"].shape == (H, W, 3) and look["image"].dtype == np.uint8
    assert look["q"].shape == (5,) and look["ee"].shape == (3,)
    assert isinstance(look["camera"], Camera) and look["camera"].width == W
    assert report["touched"] and report["frames"] > 10
    truth = robot.ground_truth_mask()
    assert truth.shape == (H, W) and truth.dtype == np.uint16
    with pytest.raises(ValueError, match="start: expected 2 numbers"):
        robot.push(np.zeros(3), np.zeros(2))


def test_episode_read_as_arrays_in_rgb_order(pushed):
    import matplotlib.image
    _, report, path = pushed
    e = Episode.read(path)
    assert len(e) == report["frames"]
    assert e.first_touch_frame == report["first_touch_frame"]
    frame = e.frame(0)
    assert frame.shape == (H, W, 3)
    # The PNG as a Python user reads it (RGB): the same pixels.
    png = matplotlib.image.imread(str(path / "frames" / "000000.png"))
    np.testing.assert_array_equal(frame, np.round(png[..., :3] * 255).astype(np.uint8))
    frames = e.frames()
    assert frames.shape == (len(e), H, W, 3)
    np.testing.assert_array_equal(frames[0], frame)
    arm = e.arm()
    assert arm["q"].shape == (len(e), 5) and arm["touching"].dtype == bool
    assert arm["touching"][e.first_touch_frame]
    with pytest.raises(IndexError):
        e.frame(len(e))


def test_segmentation_of_an_episode(pushed):
    _, _, path = pushed
    result = segment_ml(Episode.read(path), MlOptions(region_count=200))
    assert result["scored_frame"] >= 0
    assert result["map"].shape == (H, W) and result["map"].dtype == np.float32
    assert result["mask"].shape == (H, W) and result["mask"].dtype == np.uint8
    assert 0.0 <= result["map"].min() and result["map"].max() <= 1.0
    assert (result["mask"] == 255).sum() > 0
    with pytest.raises(ValueError, match="MlOptions.model must be"):
        MlOptions(model="rigid")


def test_vocabulary_quantize_is_the_nearest_word():
    rng = np.random.RandomState(0)
    descriptors = rng.rand(500, 16).astype(np.float32)
    vocabulary, summary = build_vocabulary(descriptors, KmeansOptions(words=8, threads=1))
    assert vocabulary.size == 8 and vocabulary.dimension == 16
    words = vocabulary.quantize(descriptors)
    d = ((descriptors[:, None, :] - vocabulary.words[None, :, :]) ** 2).sum(axis=2)
    np.testing.assert_array_equal(words, d.argmin(axis=1))
    with pytest.raises(ValueError, match="descriptors: expected a 2-d C-contiguous float32 array, "
                                         "got dtype float64"):
        vocabulary.quantize(descriptors.astype(np.float64))
    with pytest.raises(ValueError, match="descriptors: .*non-contiguous"):
        vocabulary.quantize(np.asfortranarray(descriptors))
    with pytest.raises(ValueError, match="descriptors: expected size 16 along axis 1"):
        vocabulary.quantize(descriptors[:, :8].copy())


def test_vocabulary_file_round_trip_and_errors(tmp_path):
    words = np.arange(24, dtype=np.float32).reshape(3, 8)
    v = Vocabulary(words)
    v.save(tmp_path / "v.bin")
    np.testing.assert_array_equal(Vocabulary.load(tmp_path / "v.bin").words, words)
    with pytest.raises(FileNotFoundError):
        Vocabulary.load(tmp_path / "missing.bin")
    (tmp_path / "bad.bin").write_bytes(b"xx")
    with pytest.raises(ValueError, match="bad.bin: not a vocabulary file"):
        Vocabulary.load(tmp_path / "bad.bin")
    with pytest.raises(FileNotFoundError):
        Episode.read(tmp_path / "no-episode")


def test_dense_features_of_an_rgb_image():
    rng = np.random.RandomState(1)
    image = (rng.rand(64, 64, 3) * 255).astype(np.uint8)
    points, descriptors = extract_features(image, ExtractOptions(kind="dense", step=16,
                                                                 min_contrast=0))
    assert descriptors.shape == (len(points), 128) and descriptors.dtype == np.float32
    assert len(points) > 0
    with pytest.raises(ValueError, match="image: expected size 3 along axis 2"):
        extract_features(image[..., :2].copy())
    with pytest.raises(ValueError, match="image: expected a 3-d C-contiguous uint8"):
        extract_features(image.astype(np.float32))


def test_run_push_returns_its_record():
    from proprio.loop import PushOptions, run_push
    result = run_push(PushOptions(), TableOptions(objects=2, seed=2, width=W, height=H))
    assert result["document"]["format"] == "proprio.push"
    assert result["message"] and "\n" not in result["message"]


def test_bag_of_words_counts_words():
    from proprio.recognition import bag_of_words
    v = Vocabulary(np.array([[0.0, 0.0], [10.0, 10.0]], dtype=np.float32))
    d = np.array([[0.1, 0.0], [9.0, 9.5], [0.0, 0.2]], dtype=np.float32)
    np.testing.assert_array_equal(bag_of_words(v, d), [2, 1])


def test_type_stubs_were_generated():
    import pathlib

    import proprio
    stubs = pathlib.Path(proprio.__file__).parent / "_proprio"
    names = {p.name for p in stubs.glob("*.pyi")}
    assert {"__init__.pyi", "topics.pyi", "sim.pyi", "features.pyi"} <= names
    assert "class LdaModel" in (stubs / "topics.pyi").read_text()
