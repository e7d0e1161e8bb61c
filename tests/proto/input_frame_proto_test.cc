// The input frame's wire form (input_frame.proto) <-> motion/frames: every preset has its enum
// value, explicit fields override a preset, and bad values are refused naming the field.
#include "proto/convert/input_frame_proto.h"

#include <gtest/gtest.h>

namespace mocap {
namespace {

TEST(InputFrameProtoTest, EveryPresetHasItsEnumValueAndBack) {
  for (const InputFramePreset& preset : InputFramePresets()) {
    const v1::InputFramePreset value = PresetToProto(preset.name);
    ASSERT_NE(value, v1::INPUT_FRAME_PRESET_UNSPECIFIED) << preset.name;
    ASSERT_TRUE(PresetFromProto(value)) << preset.name;
    EXPECT_EQ(PresetFromProto(value)->name, preset.name);
  }
  // ... and every enum value its preset.
  const google::protobuf::EnumDescriptor* values = v1::InputFramePreset_descriptor();
  for (int i = 0; i < values->value_count(); ++i) {
    const auto value = static_cast<v1::InputFramePreset>(values->value(i)->number());
    if (value == v1::INPUT_FRAME_PRESET_UNSPECIFIED) continue;
    EXPECT_TRUE(PresetFromProto(value)) << values->value(i)->name();
  }
  EXPECT_EQ(PresetToProto("maya"), v1::INPUT_FRAME_PRESET_UNSPECIFIED);
}

TEST(InputFrameProtoTest, ExplicitFieldsOverrideThePresetAndEchoInFull) {
  v1::InputFrame proto;
  proto.set_preset(v1::INPUT_FRAME_PRESET_UNREAL);
  proto.set_unit(v1::LENGTH_UNIT_MILLIMETRE);
  proto.set_calibrate_floor(true);
  proto.set_grip_offset(90);  // mm: a phone in the hand
  auto frame = InputFrameFromProto(proto);
  ASSERT_TRUE(frame.ok()) << frame.status();
  EXPECT_EQ(frame->grip_offset, 90.0f);
  EXPECT_EQ(frame->convention.unit, LengthUnit::kMillimetre);
  EXPECT_EQ(frame->convention.up, UpAxis::kPosZ);  // the preset's
  EXPECT_EQ(frame->convention.handedness, Handedness::kLeft);
  EXPECT_TRUE(frame->floor.calibrate);
  const v1::InputFrame echo = ToProto(*frame, proto.preset());
  EXPECT_EQ(echo.preset(), v1::INPUT_FRAME_PRESET_UNREAL);
  EXPECT_EQ(echo.up(), v1::UP_AXIS_POS_Z);
  EXPECT_EQ(echo.handedness(), v1::HANDEDNESS_LEFT);
  EXPECT_TRUE(echo.calibrate_floor());
  EXPECT_EQ(echo.grip_offset(), 90.0f);
  auto again = InputFrameFromProto(echo);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->convention.unit, LengthUnit::kMillimetre);
  // Nothing set: the native frame.
  auto native = InputFrameFromProto({});
  ASSERT_TRUE(native.ok());
  EXPECT_TRUE(IsNativeFrame(*native));
  // Every up axis survives the trip.
  for (UpAxis up : {UpAxis::kPosX, UpAxis::kNegX, UpAxis::kPosY, UpAxis::kNegY, UpAxis::kPosZ, UpAxis::kNegZ}) {
    InputFrame f;
    f.convention.up = up;
    EXPECT_EQ(InputFrameFromProto(ToProto(f, {}))->convention.up, up) << UpAxisName(up);
  }
}

TEST(InputFrameProtoTest, BadValuesAreRefusedNamingTheField) {
  v1::InputFrame proto;
  proto.set_up(static_cast<v1::UpAxis>(42));
  EXPECT_NE(InputFrameFromProto(proto).status().message().find("input_frame.up"), std::string::npos);
  proto = {};
  proto.set_preset(static_cast<v1::InputFramePreset>(99));
  EXPECT_NE(InputFrameFromProto(proto).status().message().find("input_frame.preset"), std::string::npos);
  proto = {};
  proto.set_tracked_device(true);
  proto.mutable_device_offset()->set_z(2.0f);
  EXPECT_NE(InputFrameFromProto(proto).status().message().find("device_offset"), std::string::npos);
  proto = {};
  proto.set_floor_height(std::numeric_limits<float>::infinity());
  EXPECT_NE(InputFrameFromProto(proto).status().message().find("floor_height"), std::string::npos);
}

}  // namespace
}  // namespace mocap
