// core/report/svg_plot.h: parity plots get equal axes and the 1:1 line, labels and
// legend entries are escaped and present, fluid plots fill their container,
// grids place one panel per cell; core/report/study_figures.h draws one panel per
// stand.
#include "core/report/svg_plot.h"

#include <gtest/gtest.h>

#include "core/report/study_figures.h"

namespace rollwear {
namespace {

int Count(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos;
       at = text.find(what, at + what.size())) {
    ++n;
  }
  return n;
}

PlotSpec Parity() {
  PlotSpec spec;
  spec.title = "F6 <top & bottom>";
  spec.x_label = "measured wear (µm)";
  spec.y_label = "predicted wear (µm)";
  spec.identity_line = true;
  PlotSeries top = PlotSeries::Make("top", "", PlotSeries::Style::kPoints);
  top.x = {120, 250, 410};
  top.y = {100, 260, 380};
  PlotSeries bottom =
      PlotSeries::Make("bottom", "#123456", PlotSeries::Style::kPoints);
  bottom.x = {150};
  bottom.y = {170};
  spec.series = {top, bottom};
  return spec;
}

TEST(SvgPlotTest, ParityPlotHasTheIdentityLineLabelsAndLegend) {
  const std::string svg = RenderSvg(Parity());
  EXPECT_EQ(svg.rfind("<svg ", 0), 0u);
  EXPECT_NE(svg.find("width=\"520\" height=\"380\""), std::string::npos);
  EXPECT_EQ(Count(svg, "class=\"identity\""), 1);
  EXPECT_NE(svg.find(">1:1 ↗</text>"), std::string::npos);
  EXPECT_NE(svg.find("F6 &lt;top &amp; bottom&gt;"), std::string::npos);
  EXPECT_NE(svg.find(">measured wear (µm)</text>"), std::string::npos);
  EXPECT_NE(svg.find(">predicted wear (µm)</text>"), std::string::npos);
  EXPECT_NE(svg.find(">top</text>"), std::string::npos);
  EXPECT_NE(svg.find(">bottom</text>"), std::string::npos);
  // 4 data points plus 2 legend markers; an unset colour takes the palette's.
  EXPECT_EQ(Count(svg, "<circle"), 6);
  EXPECT_NE(svg.find(PaletteColor(0)), std::string::npos);
  EXPECT_NE(svg.find("#123456"), std::string::npos);
  EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
}

TEST(SvgPlotTest, IdentityLineSpansEqualAxes) {
  const std::string svg = RenderSvg(Parity());
  // The data span 100..410 on both axes once made equal: ticks 100..500 step
  // 100 label both axes identically, so each label appears twice.
  for (const char* tick :
       {">100</text>", ">200</text>", ">300</text>", ">400</text>"}) {
    EXPECT_EQ(Count(svg, tick), 2) << tick;
  }
}

TEST(SvgPlotTest, FluidPlotFillsItsContainerAndLegendCanBeOff) {
  PlotSpec spec = Parity();
  spec.fluid = true;
  spec.legend = PlotSpec::Legend::kNone;
  const std::string svg = RenderSvg(spec);
  EXPECT_NE(svg.find("width=\"100%\" viewBox=\"0 0 520 380\""),
            std::string::npos);
  EXPECT_EQ(svg.find(">top</text>"), std::string::npos);
  EXPECT_EQ(Count(svg, "<circle"), 4);
}

TEST(SvgPlotTest, LinesAndEmptySeriesRender) {
  PlotSpec spec;
  spec.x_label = "rolled length (km)";
  spec.y_label = "wear (µm)";
  PlotSeries line = PlotSeries::Make("F6 top", "", PlotSeries::Style::kLine);
  line.x = {0, 1, 2};
  line.y = {0, 5, 12};
  spec.series = {line};
  const std::string svg = RenderSvg(spec);
  EXPECT_EQ(Count(svg, "<polyline"), 1);
  EXPECT_EQ(svg.find("class=\"identity\""), std::string::npos);
  spec.series.clear();
  EXPECT_NE(RenderSvg(spec).find("</svg>"), std::string::npos);
}

TEST(SvgPlotTest, GridPlacesEachPanelInItsCell) {
  const std::vector<PlotSpec> panels = {Parity(), Parity(), Parity()};
  const std::string svg = RenderSvgGrid("Laws", panels, 2);
  EXPECT_NE(svg.find("width=\"1040\" height=\"790\""), std::string::npos);
  EXPECT_NE(svg.find("<svg x=\"0\" y=\"30\""), std::string::npos);
  EXPECT_NE(svg.find("<svg x=\"520\" y=\"30\""), std::string::npos);
  EXPECT_NE(svg.find("<svg x=\"0\" y=\"410\""), std::string::npos);
  EXPECT_EQ(Count(svg, "class=\"identity\""), 3);
}

TEST(SvgPlotTest, StudyParityFigureHasOnePanelPerStand) {
  const std::vector<int> stands = {6, 7, 6, 7};
  const std::vector<double> measured = {100, 200, 300, 400};
  ParitySeries a{"Wang", "", {110, 190, 290, 420}};
  ParitySeries b{"Cao", "", {90, 210, 310, 380}};
  const std::string svg = ParityFigureSvg("laws", stands, measured, {a, b});
  EXPECT_NE(svg.find(">stand F6</text>"), std::string::npos);
  EXPECT_NE(svg.find(">stand F7</text>"), std::string::npos);
  EXPECT_EQ(Count(svg, "class=\"identity\""), 2);
  // 8 points plus 2 legend markers per panel.
  EXPECT_EQ(Count(svg, "<circle"), 12);
  EXPECT_NE(svg.find(">calculated centre wear (µm)</text>"), std::string::npos);
}

}  // namespace
}  // namespace rollwear
