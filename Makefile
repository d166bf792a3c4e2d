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

# The demo on the sample scene: validate its configurations and cameras, score how much
# neighbouring views differ (what view synthesis has to bridge), write previews and z maps.
DEMO := $(BUILD)/demo
LINE := sample_data/line
demo: install
	mkdir -p $(DEMO)
	$(BIN)/mvtools inspect $(LINE)/synthesize_cam2.cfg $(LINE)/depth_cam2.cfg
	$(BIN)/mvtools inspect sample_data/arc/cameras.txt
	$(BIN)/mvtools evaluate $(LINE)/v2_texture_256x192_yuv420p.yuv $(LINE)/v1_texture_256x192_yuv420p.yuv
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
