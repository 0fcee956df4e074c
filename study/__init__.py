"""The end-to-end design study (``ccedi study``): TOML inputs, orchestration of the
identification, ROM, design, FEA re-check and calibration steps, and the HTML report."""
