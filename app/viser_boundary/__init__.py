"""The one place that reaches into viser's private internals.

viser 1.1.1 offers no public API for these, and each is checked by a test of its own
(``tests/test_viser_boundary.py``); :func:`check_viser_version` refuses to start on a
viser whose internals were not checked:

* :func:`make_viser_server`: our page title (a copy of viser's page), no share tunnel, on
  phones the panel as a sheet below the canvas (:data:`PHONE_LAYOUT`), no text of viser's
  below 11 px (:data:`READABLE_TEXT`);
* :func:`harden_websocket`: the websocket refuses messages over :data:`WS_MAX_BYTES` before
  reading them (the transport's ``max_size``), only :data:`ALLOWED_MESSAGES` reach viser's
  handlers, each connection is paced (a flooding page waits on its own socket) and waits
  while its callbacks queue up;
* :func:`order_callbacks`: one connection's callbacks run in the order its messages came,
  round-robin over connections within a CPU budget (:class:`OrderedExecutor`); each
  callback reads the value its page sent (:func:`sent_value`), not the widget's value when
  it runs;
* :func:`client_address`: the network address a page connected from;
* :func:`send_lag`, :func:`send_progress`: how many messages a page's sender is behind (a
  page that does not read), and whether its sender is taking any;
* :class:`WakeBatch`: the messages of one frame-loop tick wake viser's loop once;
* :func:`fast_set`: one property of a handle set on the hot path;
* :func:`recording_scene`: a scene API whose messages are only recorded (HTML replay);
* :func:`guard_gui_updates`: a GUI value of the wrong type is refused with one message
  to its sender;
* :func:`event_loop`: the server's own event loop (the frame loop runs in it);
* :func:`relabel_tabs`: a tab group's labels changed in place (a page's language switched).

The face of a package: each concern is a private module (``_patches``, ``_websocket``, ``_backlog``,
``_callbacks``, ``_page``, ``_hot_path``, ``_recording``, ``_gui_guard``, ``_tabs``); the rest of the
lab imports only the names below.
"""

from analyzer_lab.viser_boundary._backlog import send_lag as send_lag
from analyzer_lab.viser_boundary._backlog import send_progress as send_progress
from analyzer_lab.viser_boundary._callbacks import CONNECTION as CONNECTION
from analyzer_lab.viser_boundary._callbacks import OrderedExecutor as OrderedExecutor
from analyzer_lab.viser_boundary._callbacks import order_callbacks as order_callbacks
from analyzer_lab.viser_boundary._callbacks import sent_value as sent_value
from analyzer_lab.viser_boundary._callbacks import submit_callback as submit_callback
from analyzer_lab.viser_boundary._gui_guard import guard_gui_updates as guard_gui_updates
from analyzer_lab.viser_boundary._gui_guard import value_problem as value_problem
from analyzer_lab.viser_boundary._hot_path import WakeBatch as WakeBatch
from analyzer_lab.viser_boundary._hot_path import event_loop as event_loop
from analyzer_lab.viser_boundary._hot_path import fast_set as fast_set
from analyzer_lab.viser_boundary._hot_path import set_pose as set_pose
from analyzer_lab.viser_boundary._page import FOLLOW_LANGUAGE as FOLLOW_LANGUAGE
from analyzer_lab.viser_boundary._page import KEYS_STAY_IN_FIELDS as KEYS_STAY_IN_FIELDS
from analyzer_lab.viser_boundary._page import PAGE_TITLE as PAGE_TITLE
from analyzer_lab.viser_boundary._page import PHONE_LAYOUT as PHONE_LAYOUT
from analyzer_lab.viser_boundary._page import READABLE_TEXT as READABLE_TEXT
from analyzer_lab.viser_boundary._page import language_marker as language_marker
from analyzer_lab.viser_boundary._page import make_viser_server as make_viser_server
from analyzer_lab.viser_boundary._patches import VISER_VERSION as VISER_VERSION
from analyzer_lab.viser_boundary._patches import check_viser_version as check_viser_version
from analyzer_lab.viser_boundary._recording import recording_scene as recording_scene
from analyzer_lab.viser_boundary._tabs import relabel_tabs as relabel_tabs
from analyzer_lab.viser_boundary._websocket import ALLOWED_MESSAGES as ALLOWED_MESSAGES
from analyzer_lab.viser_boundary._websocket import WS_DROPPED_TYPES as WS_DROPPED_TYPES
from analyzer_lab.viser_boundary._websocket import WS_MAX_BYTES as WS_MAX_BYTES
from analyzer_lab.viser_boundary._websocket import WS_STATS as WS_STATS
from analyzer_lab.viser_boundary._websocket import client_address as client_address
from analyzer_lab.viser_boundary._websocket import dropped_types as dropped_types
from analyzer_lab.viser_boundary._websocket import harden_websocket as harden_websocket
