"""Tumble's Python post-processing: the ensemble report (report.py and its report_* modules),
bottom-view renders (render_bottom.py) and plots of single runs. Run as scripts
(/usr/bin/python3 postproc/report.py ...) or as modules (python3 -m postproc.report ...)."""
