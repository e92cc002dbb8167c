"""``csl camera calibrate``: calibrate the overhead camera from the marker board.

One image (from the driver, or a saved one) showing the board's markers gives the
lens and the image-to-floor mapping (planner/calibration.py); the image, rectified,
is also kept as the empty floor that real-camera vision compares with
(planner/segmentation.py). docs/camera.md has the steps.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

import hero_driver.worlds
from executive import defaults
from csl_cli.args import endpoint
from zenoh_rpc.endpoints import CONNECT_KEY, DRIVER_ENDPOINT
from zenoh_rpc.options import endpoint_of, user_config

if TYPE_CHECKING:
    import numpy as np

DEFAULT_BOARD = Path(hero_driver.worlds.__file__).parent / "lab-board.json"  # the simulator's lab


def default_calibration(robot: str) -> Path:
    """``$CSL_HOME/camera/ROBOT.json``: where calibrate writes unless ``--out`` says
    otherwise (an episode reads the file ``--camera-calibration`` names)."""
    return defaults.library_db().parent / "camera" / f"{robot}.json"


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("camera", help="the overhead camera: calibrate it from the printed marker board",
                       description="Overhead camera tools (docs/camera.md).")
    commands = p.add_subparsers(dest="camera_command", metavar="COMMAND", required=True)
    cal = commands.add_parser(
        "calibrate", help="lens and image-to-floor mapping from the marker board; keep the empty floor",
        description=("Take one overhead image from the driver (or --image), find the board's ArUco markers, "
                     "fit the lens distortion and the image-to-floor homography, and write the calibration "
                     "file with the rectified image beside it as the empty floor (clear the floor of objects "
                     "first where you can; objects left on it are painted out). Prints the reprojection "
                     "error in inches."))
    cal.add_argument("--robot", default="r1", help="robot whose camera to calibrate (zenoh keys hero/ROBOT/...)")
    cal.add_argument("--connect", type=endpoint, default=None, metavar="ENDPOINT",
                     help=f"zenoh endpoint of the driver node (default {DRIVER_ENDPOINT})")
    cal.add_argument("--zenoh-config", type=Path, default=None, metavar="FILE",
                     help="the zenoh client settings (docs/security.md)")
    cal.add_argument("--image", type=Path, default=None, metavar="FILE.png",
                     help="calibrate from this saved grayscale image instead of asking the driver")
    cal.add_argument("--board", type=Path, default=DEFAULT_BOARD, metavar="FILE",
                     help="the marker board: where each marker is printed (default: the lab's)")
    cal.add_argument("--out", type=Path, default=None, metavar="FILE",
                     help="calibration file to write (default $CSL_HOME/camera/ROBOT.json)")
    cal.set_defaults(handler=run_calibrate)


def run_calibrate(args: argparse.Namespace) -> int:
    # OpenCV and the planner load only when calibrating (``csl --help`` stays light).
    from camera_model.board import load_board
    from planner.segmentation import calibrated_camera, empty_floor_path, save_camera

    board = load_board(args.board)
    out = args.out or default_calibration(args.robot)
    if out.is_dir():
        raise ValueError(f"--out: {out} is a folder, not a calibration file")
    pixels = _image_file(args.image) if args.image is not None else _driver_image(args)
    camera = calibrated_camera(pixels, board)
    calibration = camera.calibration
    out.parent.mkdir(parents=True, exist_ok=True)
    save_camera(calibration, calibration.rectify(pixels), out)
    print(f"calibrated from {calibration.markers_seen} of {len(board.markers)} markers: reprojection error "
          f"{calibration.error_in:.2f} in (RMS over {4 * calibration.markers_seen} corners); "
          f"floor {calibration.floor_size[0]}x{calibration.floor_size[1]} pixels of "
          f"{calibration.inches_per_pixel:g} in")
    print(f"wrote {out} and {empty_floor_path(out)}")
    return 0


def _image_file(path: Path) -> np.ndarray:
    import cv2

    pixels = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE) if path.is_file() else None
    if pixels is None:
        raise ValueError(f"--image: {path} is not a readable image file")
    return pixels


def _driver_image(args: argparse.Namespace) -> np.ndarray:
    import numpy as np

    from hero_driver.interface import UNAVAILABLE, DriverError
    from hero_driver.zenoh_link.client import ZenohDriver

    zenoh_config = user_config(args.zenoh_config)
    connect = endpoint_of("--connect", args.connect, DRIVER_ENDPOINT, CONNECT_KEY, zenoh_config)
    driver = ZenohDriver(args.robot, connect=[connect], discover_s=3.0, zenoh_config=zenoh_config)
    try:
        if not driver.wait_ready(5.0):
            raise DriverError(UNAVAILABLE, f"no driver is serving robot {args.robot!r} at {connect}; start one "
                                           f"with 'csl driver sim --robot {args.robot} --camera realistic'")
        return np.asarray(driver.camera().result(timeout=60).pixels)
    finally:
        driver.close()
