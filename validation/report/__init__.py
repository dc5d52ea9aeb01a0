"""The report: Markdown sections, CSV tables and figures (names and styles from
:mod:`validation.common.labels`), assembled by :func:`validation.report.write.write_report`."""
