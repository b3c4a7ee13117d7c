"""`lerobot-train` with the project's quiet video libraries: one line saying PyAV decodes instead of lerobot's
~60-line torchcodec traceback on every dataset open (mobilemani_data.video). Same arguments:

    python -m mobilemani_vla.lerobot_train --policy.type=act --dataset.root=<dataset> ...
"""

from __future__ import annotations

from mobilemani_data.video import quiet_video_libraries


def main() -> None:
    quiet_video_libraries()
    # Imported after the log filter is in place: lerobot warns about torchcodec while importing.
    from lerobot.scripts.lerobot_train import main as lerobot_train

    lerobot_train()


if __name__ == "__main__":
    main()
