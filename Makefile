# mvtools: the project's entry points. `make demo` and `make test` are the README's two commands.
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
BUILD ?= build

.DELETE_ON_ERROR:
.PHONY: install sample demo test bench clean

install: $(VENV)/.installed

$(VENV)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $@

# Regenerate the committed sample data from the project's own synthetic scene.
sample: install
	$(BIN)/mvtools scene sample_data

# The demo on the sample scene: validate its configurations and cameras, synthesize camera 2
# of the line (1D mode) and of the arc (general mode) from its neighbours and score the result
# against the real view 2 (and, for contrast, the neighbouring view itself), write previews.
DEMO := $(BUILD)/demo
LINE := sample_data/line
ARC := sample_data/arc
VIEW := 256x192_yuv420p.yuv
demo: install
	mkdir -p $(DEMO)
	$(BIN)/mvtools inspect $(LINE)/synthesize_cam2.cfg $(LINE)/depth_cam2.cfg
	$(BIN)/mvtools inspect $(ARC)/cameras.txt
	$(BIN)/mvtools synthesize $(LINE)/synthesize_cam2.cfg -o $(DEMO)/line_v2_synthesized_$(VIEW)
	$(BIN)/mvtools synthesize $(ARC)/synthesize_cam2.cfg -o $(DEMO)/arc_v2_synthesized_$(VIEW)
	$(BIN)/mvtools evaluate $(LINE)/v2_texture_$(VIEW) $(DEMO)/line_v2_synthesized_$(VIEW)
	$(BIN)/mvtools evaluate $(ARC)/v2_texture_$(VIEW) $(DEMO)/arc_v2_synthesized_$(VIEW)
	$(BIN)/mvtools evaluate $(LINE)/v2_texture_$(VIEW) $(LINE)/v1_texture_$(VIEW)
	$(BIN)/mvtools convert $(DEMO)/line_v2_synthesized_$(VIEW) -o $(DEMO)/line_v2_synthesized_%02d.png
	$(BIN)/mvtools convert $(LINE)/v2_texture_256x192_yuv420p.yuv -o $(DEMO)/v2_texture_%02d.png
	$(BIN)/mvtools convert $(LINE)/v2_depth_256x192_yuv420p.yuv --depth --preview -o $(DEMO)/v2_depth_%02d.png
	$(BIN)/mvtools convert $(LINE)/v2_depth_256x192_gray16le.yuv --depth --to z --znear 2 --zfar 13 -o $(DEMO)/v2_z_%02d.pfm
	@echo "demo outputs in $(DEMO)"

test: install
	$(BIN)/python -m pytest -q

bench: install
	$(BIN)/python benchmarks/run.py

clean:
	rm -rf $(BUILD)
