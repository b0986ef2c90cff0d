"""Watch a running robot's log with a saved model: winding estimates, forecasts and derating, as ROS 2
messages in an MCAP, on Foxglove's live WebSocket, or as JSON lines (``thermolimb monitor``)."""

from .estimator import ActuatorMonitor, Estimate
from .session import Session, follow

__all__ = ["ActuatorMonitor", "Estimate", "Session", "follow"]
