"""The report: Markdown sections, CSV tables, figures and labels, assembled by
:func:`validation.report.write.write_report`."""
