from mvtools.cli.main import cli

cli(prog_name="mvtools")
