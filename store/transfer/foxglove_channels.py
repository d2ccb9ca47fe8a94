"""The channels an MCAP export draws a run on, as Foxglove and Lichtblick read them: their topics,
Foxglove's well-known schema for each, and the mark that tells an import they are views, not evidence.

Kept apart from the drawing (foxglove.py) so that reading a file, which only needs to know these
channels to skip them, does not load foxglove-sdk.
"""

from __future__ import annotations

MAP_TOPIC, ENTITIES_TOPIC, SIGNALS_TOPIC, LOG_TOPIC = "/scene/map", "/scene/entities", "/scene/signals", "/log"
SCENE_UPDATE, LOG = "foxglove.SceneUpdate", "foxglove.Log"
TOPICS = {MAP_TOPIC: SCENE_UPDATE, ENTITIES_TOPIC: SCENE_UPDATE, SIGNALS_TOPIC: SCENE_UPDATE, LOG_TOPIC: LOG}
DERIVED_MARK = "gaps.derived"  # channel metadata key marking these channels as drawn, not evidence
ENCODING = "protobuf"  # message and schema encoding of these channels, as foxglove-sdk writes them
