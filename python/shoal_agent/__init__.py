"""Alias of :mod:`shoal.agent`, the shared-memory agent API, under its former name: code that
imports ``shoal_agent`` (or ``shoal_agent.agent``, ``shoal_agent.protocol``) keeps working.
New code should import ``shoal.agent``.
"""

import sys

from shoal.agent import *  # noqa: F401,F403 (the alias re-exports everything)
from shoal.agent import __all__  # noqa: F401
from shoal.agent import agent, protocol

sys.modules[__name__ + ".agent"] = agent
sys.modules[__name__ + ".protocol"] = protocol
