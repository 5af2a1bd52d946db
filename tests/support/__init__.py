"""What the tests share: servers, pages, waiting and measuring (imported by the tests and
by ``benchmarks/``, never by the package).

``waiting`` waits on a condition with a deadline; ``wire`` speaks viser's protocol;
``client`` is one page as a websocket client; ``servers`` starts ``analyzer_lab serve``
subprocesses; ``redis_server`` a redis-server; ``browser`` drives Chromium through
Playwright; ``load`` measures what pages receive; ``stepping_attacks`` the attacks on the
stepping; ``surfaces`` and ``integrator_problems`` are shared test data.
"""
