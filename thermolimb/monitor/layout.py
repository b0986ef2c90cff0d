"""A Foxglove layout for the monitor's channels: a plot of each actuator's estimated and measured
temperature, and the diagnostics panel.  ``thermolimb/data/foxglove_layout.json`` is this layout for the
plant's knee, hip and ankle; ``thermolimb monitor --layout FILE`` writes it for the actuators being watched
(import it in Foxglove: Layouts, Import from file)."""

from __future__ import annotations

import json

SHIPPED_ACTUATORS = ("knee", "hip", "ankle")
COLOURS = ("#4e98e2", "#f5774d", "#61cbff", "#f7df71", "#d37ac6", "#9cdc6b")


MARK = '"/thermolimb/'  # every layout this suite writes plots its topics: a file --layout may replace


def layout(actuators) -> dict:
    plot_paths = []
    for i, a in enumerate(actuators):
        colour = COLOURS[i % len(COLOURS)]
        plot_paths += [
            {
                "value": f"/thermolimb/{a}/winding_temperature.temperature",
                "enabled": True,
                "timestampMethod": "receiveTime",
                "label": f"{a} winding (estimated, degC)",
                "color": colour,
            },
            {
                "value": f"/thermolimb/{a}/measured_temperature.temperature",
                "enabled": True,
                "timestampMethod": "receiveTime",
                "label": f"{a} measured (degC)",
                "color": colour,
                "lineSize": 0.5,
            },
        ]
    return {
        "configById": {
            "Plot!temperatures": {
                "title": "winding temperature: estimated and measured (degC)",
                "paths": plot_paths,
                "showXAxisLabels": True,
                "showYAxisLabels": True,
                "showLegend": True,
                "legendDisplay": "floating",
                "isSynced": True,
                "xAxisVal": "timestamp",
            },
            "DiagnosticSummary!thermal": {
                "minLevel": 0,
                "pinnedIds": [],
                "hardwareIdFilter": "",
                "topicToRender": "/diagnostics",
                "sortByLevel": True,
            },
            "DiagnosticStatusPanel!detail": {"topicToRender": "/diagnostics", "collapsedSections": []},
        },
        "globalVariables": {},
        "userNodes": {},
        "layout": {
            "first": "Plot!temperatures",
            "second": {
                "first": "DiagnosticSummary!thermal",
                "second": "DiagnosticStatusPanel!detail",
                "direction": "column",
                "splitPercentage": 50,
            },
            "direction": "row",
            "splitPercentage": 65,
        },
    }


def layout_text(actuators) -> str:
    return json.dumps(layout(actuators), indent=2) + "\n"
