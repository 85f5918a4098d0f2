"""rigserver.reports: what a run gives back to people: its report and its data for download.

- :mod:`~rigserver.reports.run_report`: ``build_report`` (a run, its results, its readings
  -> a :class:`~rigserver.reports.document.Report`) and ``render_report`` (-> HTML);
  :mod:`~rigserver.reports.labs` holds one module per lab work (the manual's tables, plots
  and conclusions of a stand).
- :mod:`~rigserver.reports.pdf`: the PDF of the same HTML (WeasyPrint, A4).
- :mod:`~rigserver.reports.export`: CSV of the readings and the results, the zip of a run.
- :mod:`~rigserver.reports.i18n`: English and Russian; :mod:`~rigserver.reports.formatting`:
  numbers (four significant figures) and symbols; :mod:`~rigserver.reports.plots`: SVG.
- :mod:`~rigserver.reports.mechanism`: the page of the lever-mechanism calculator.

Reports read runs through :class:`rigserver.analysis.Readings`, handed in by the API layer;
they import neither the API nor the storage.
"""
