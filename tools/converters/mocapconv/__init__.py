"""Device logs to the wrist CSV of `mocap reconstruct --csv` (tools/converters/mocap_convert.py).

One module per source (openxr, webxr, arkit, unity, unreal, mediapipe), each reading its log into
hand samples in the source's own frame; frames.py (conventions, rotations), logs.py (reading with
FILE:LINE errors), pose_rows.py (the per-hand CSV OpenXR, Unity and Unreal share) and wrists.py
(frames, conversion, the CSV writer) are shared. docs/devices/README.md describes each log.
"""
