// The controller buttons as a study's answers (study --display xr): each procedure's answers on
// the buttons a participant keeps across procedures, nothing where a phase takes no answer.
#include <gtest/gtest.h>

#include "study_xr_buttons.hpp"

namespace gt {
namespace {

using study::Response;

TEST(StudyXrButtons, EachProcedureAnswersOnItsButtons) {
    const std::vector<Response> choice = {Response::First, Response::Second};
    EXPECT_EQ(app::responseOfButton(0, choice), Response::First);
    EXPECT_EQ(app::responseOfButton(1, choice), Response::Second);
    EXPECT_EQ(app::responseOfButton(2, choice), std::nullopt);
    EXPECT_EQ(app::responseOfButton(3, choice), std::nullopt);

    const std::vector<Response> yesNo = {Response::Yes, Response::No};
    EXPECT_EQ(app::responseOfButton(0, yesNo), Response::Yes);
    EXPECT_EQ(app::responseOfButton(1, yesNo), Response::No);

    const std::vector<Response> pair = {Response::First, Response::Second, Response::Same};
    EXPECT_EQ(app::responseOfButton(2, pair), Response::Same);

    const std::vector<Response> ramp = {Response::Up, Response::Down, Response::Same};
    EXPECT_EQ(app::responseOfButton(0, ramp), Response::Up);
    EXPECT_EQ(app::responseOfButton(1, ramp), Response::Down);
    EXPECT_EQ(app::responseOfButton(2, ramp), Response::Same);

    const std::vector<Response> slider = {Response::Up, Response::Down, Response::Reference,
                                          Response::Accept};
    EXPECT_EQ(app::responseOfButton(0, slider), Response::Up);
    EXPECT_EQ(app::responseOfButton(1, slider), Response::Down);
    EXPECT_EQ(app::responseOfButton(2, slider), Response::Reference);
    EXPECT_EQ(app::responseOfButton(3, slider), Response::Accept);
}

TEST(StudyXrButtons, AnyButtonGoesOnAndNothingAnswersWhereNothingIsAsked) {
    const std::vector<Response> go = {Response::Continue};
    for (uint32_t b = 0; b < 4; ++b)
        EXPECT_EQ(app::responseOfButton(b, go), Response::Continue) << b;
    EXPECT_EQ(app::responseOfButton(4, go), std::nullopt); // no such button
    for (uint32_t b = 0; b < 4; ++b)
        EXPECT_EQ(app::responseOfButton(b, {}), std::nullopt) << b; // an interval, a blank
    EXPECT_EQ(app::buttonPrompt(go), "any button: continue");
    EXPECT_EQ(app::buttonPrompt(std::vector<Response>{Response::Yes, Response::No}),
              "left trigger: yes  right trigger: no");
}

} // namespace
} // namespace gt
