"""Unpack the wheels that a lent GPU machine (no network) lacks into a site directory, over nothing it has:

python3 docs/results/gpu_ppo/unpack_wheels.py <site> <wheel_dir>
"""

import importlib.metadata
import pathlib
import re
import sys
import zipfile


def main(site: str, wheels: str) -> None:
    for wheel in sorted(pathlib.Path(wheels).glob("*.whl")):
        dist = re.sub(r"[-_.]+", "-", wheel.name.split("-")[0]).lower()
        try:
            print(f"have {dist} {importlib.metadata.version(dist)}")
        except importlib.metadata.PackageNotFoundError:
            zipfile.ZipFile(wheel).extractall(site)
            print(f"unpacked {wheel.name}")


if __name__ == "__main__":
    main(*sys.argv[1:])
