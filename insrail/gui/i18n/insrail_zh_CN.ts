<?xml version="1.0" encoding="utf-8"?>
<!DOCTYPE TS>
<TS version="2.1" language="zh_CN">
  <context>
    <name>insrail</name>
    <message>
      <location filename="../../../insrail/gui/choices.py" line="36" />
      <source>True</source>
      <translation>是</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/choices.py" line="36" />
      <source>False</source>
      <translation>否</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/empty.py" line="40" />
      <source>No project open. File &gt; New project… creates one from raw files; File &gt; Open project… opens a project.toml.</source>
      <translation>未打开项目。“文件 &gt; 新建项目…”从原始数据创建项目；“文件 &gt; 打开项目…”打开 project.toml。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/empty.py" line="75" />
      <source>Write the out-of-date reports again, at their places, from the current results</source>
      <translation>按当前结果在原位置重新生成过期的报告</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/empty.py" line="55" />
      <source>This project has no survey yet: File &gt; Import raw files… adds one.</source>
      <translation>此项目尚无测量：“文件 &gt; 导入原始数据…”添加测量。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/empty.py" line="93" />
      <source>Write it again</source>
      <translation>重新生成</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/empty.py" line="93" />
      <source>Write them again</source>
      <translation>全部重新生成</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/empty.py" line="47" />
      <source>Reading the results of {project}…</source>
      <translation>正在读取 {project} 的结果…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/empty.py" line="119" />
      <source>Process {survey}</source>
      <translation>处理 {survey}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/empty.py" line="59" />
      <source>Survey {survey} has no results yet: the track, plan and navigation views stay empty until it is processed.</source>
      <translation>测量 {survey} 尚无结果：处理之前，轨道、平面和导航视图为空。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/empty.py" line="116" />
      <source>Survey {survey} was processed before its events ({events}) changed: its results, plots and exceedances do not show them yet. Process it again.</source>
      <translation>测量 {survey} 在其线路事件（{events}）修改之前处理：其结果、曲线和超限尚未反映这些事件。请重新处理。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/empty.py" line="88" />
      <source>The report {names} of survey {survey} was written before the survey was processed again: it describes results that no longer exist.</source>
      <translation>测量 {survey} 的报告 {names} 生成于重新处理之前：其内容对应的结果已不存在。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/empty.py" line="90" />
      <source>The reports {names} of survey {survey} were written before the survey was processed again: they describe results that no longer exist.</source>
      <translation>测量 {survey} 的报告 {names} 生成于重新处理之前：其内容对应的结果已不存在。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/empty.py" line="92" />
      <source> and </source>
      <translation>、</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/event_dialog.py" line="37" />
      <source>Mark as track event</source>
      <translation>标记为线路事件</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/event_dialog.py" line="47" />
      <source>empty: a point (a joint, a note)</source>
      <translation>留空：单点（接头、备注）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/event_dialog.py" line="49" />
      <source>optional: W12 No. 18 right-hand, LC 3, …</source>
      <translation>可选：W12 18号右开道岔、LC 3 …</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/event_dialog.py" line="70" />
      <source>Mark</source>
      <translation>标记</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/event_dialog.py" line="52" />
      <source>Kind</source>
      <translation>类型</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/event_dialog.py" line="52" />
      <source>From station [m]</source>
      <translation>起点测站里程 [m]</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/event_dialog.py" line="53" />
      <source>To station [m]</source>
      <translation>终点测站里程 [m]</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/event_dialog.py" line="53" />
      <source>Note</source>
      <translation>说明</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/event_dialog.py" line="60" />
      <source>{file} (new; the project will name it)</source>
      <translation>{file}（新建；项目将引用它）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/event_dialog.py" line="61" />
      <source>Appended to the project's event file {file}; the surveys need processing again to assess with it.</source>
      <translation>追加到项目的事件文件 {file}；各测量需重新处理才能据此评估。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/event_dialog.py" line="106" />
      <source>a station is needed</source>
      <translation>需要测站里程</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/event_dialog.py" line="109" />
      <source>expected a finite station, found {text}</source>
      <translation>应为有限的测站里程，实为 {text}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/event_dialog.py" line="125" />
      <source>Not marked: {error}</source>
      <translation>未标记：{error}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/event_dialog.py" line="105" />
      <source>expected a station in metres, found {text}</source>
      <translation>应为以米计的测站里程，实为 {text}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="65" />
      <source>Surveys</source>
      <translation>测量</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="66" />
      <source>Results</source>
      <translation>结果</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="52" />
      <source>Project</source>
      <translation>项目</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="214" />
      <source>Property</source>
      <translation>属性</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="214" />
      <source>Value</source>
      <translation>值</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="96" />
      <source>written before the survey was processed again: it describes results that no longer exist</source>
      <translation>生成于测量重新处理之前：其内容对应的结果已不存在</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="139" />
      <source>Write the out-of-date reports again</source>
      <translation>重新生成过期的报告</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="165" />
      <source>folder</source>
      <translation>文件夹</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="165" />
      <source>coordinate system</source>
      <translation>坐标系</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="94" />
      <source>⚠ {name} (older than the results)</source>
      <translation>⚠ {name}（早于结果）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="98" />
      <source>written from the current results: {path}</source>
      <translation>由当前结果生成：{path}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="130" />
      <source>Show results of {survey}</source>
      <translation>显示 {survey} 的结果</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="131" />
      <source>Process {survey} again</source>
      <translation>重新处理 {survey}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="179" />
      <source>role</source>
      <translation>用途</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="179" />
      <source>path</source>
      <translation>路径</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="179" />
      <source>format</source>
      <translation>格式</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="180" />
      <source>size</source>
      <translation>大小</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="135" />
      <source>Write the out-of-date reports of {survey} again</source>
      <translation>重新生成 {survey} 的过期报告</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="173" />
      <source>problem</source>
      <translation>问题</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="180" />
      <source>missing</source>
      <translation>缺失</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="181" />
      <source>option {name}</source>
      <translation>选项 {name}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="191" />
      <source>file</source>
      <translation>文件</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="192" />
      <source>state</source>
      <translation>状态</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="192" />
      <source>older than the results: written before the survey was processed again</source>
      <translation>早于结果：生成于重新处理之前</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/explorer.py" line="193" />
      <source>written from the current results</source>
      <translation>按当前结果生成</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/export_files.py" line="25" />
      <source>Excel workbook</source>
      <translation>Excel 工作簿</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/export_files.py" line="25" />
      <source>Excel workbook (*.xlsx)</source>
      <translation>Excel 工作簿 (*.xlsx)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/export_files.py" line="26" />
      <source>PDF report</source>
      <translation>PDF 报告</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/export_files.py" line="26" />
      <source>PDF report (*.pdf)</source>
      <translation>PDF 报告 (*.pdf)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/export_files.py" line="28" />
      <source>&amp;Lift/lining table…</source>
      <translation>起拨道量表(&amp;L)…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/export_files.py" line="28" />
      <source>Lift/lining table (*.csv)</source>
      <translation>起拨道量表 (*.csv)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/export_files.py" line="29" />
      <source>&amp;DXF drawing…</source>
      <translation>DXF 图(&amp;D)…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/export_files.py" line="29" />
      <source>DXF drawing (*.dxf)</source>
      <translation>DXF 图 (*.dxf)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/export_files.py" line="30" />
      <source>Measured lines as &amp;LandXML…</source>
      <translation>实测线形 LandXML(&amp;L)…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/export_files.py" line="30" />
      <source>LandXML (*.xml)</source>
      <translation>LandXML (*.xml)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/export_files.py" line="31" />
      <source>Sleeper &amp;coordinates…</source>
      <translation>轨枕坐标(&amp;C)…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/export_files.py" line="31" />
      <source>CSV (*.csv)</source>
      <translation>CSV (*.csv)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/export_files.py" line="80" />
      <source>Export failed</source>
      <translation>导出失败</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/export_files.py" line="93" />
      <source>exporting the {what} of {survey} to {path}</source>
      <translation>正在将测量 {survey} 的{what}导出至 {path}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/export_files.py" line="137" />
      <source>reports of {survey}</source>
      <translation>测量 {survey} 的报告</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/export_files.py" line="138" />
      <source>writing {files} again from the results of {survey}</source>
      <translation>正在根据测量 {survey} 的结果重新生成 {files}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/export_files.py" line="39" />
      <source>Export the survey shown: {what}</source>
      <translation>导出当前测量：{what}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/export_files.py" line="53" />
      <source>Export the {what} of {survey}</source>
      <translation>导出测量 {survey} 的{what}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="65" />
      <source>line</source>
      <translation>行</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="65" />
      <source>row</source>
      <translation>记录</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="110" />
      <source>letters, digits, '.', '_' or '-'</source>
      <translation>字母、数字、“.”、“_”或“-”</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="113" />
      <source>from the files</source>
      <translation>取自文件</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="135" />
      <source>Starts on a station of the design (before the first position fix)</source>
      <translation>从设计线路上的已知里程起测（首个定位之前）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="143" />
      <source>increasing stations</source>
      <translation>里程增加方向</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="144" />
      <source>decreasing stations</source>
      <translation>里程减小方向</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="146" />
      <source>Station</source>
      <translation>里程</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="147" />
      <source>Offset right of the centreline</source>
      <translation>偏离线路中线（向右）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="148" />
      <source>Height above the profile</source>
      <translation>高于设计纵断面</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="149" />
      <source>1-sigma of the start point</source>
      <translation>起测点中误差（1σ）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="150" />
      <source>The trolley faces</source>
      <translation>小车朝向</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="152" />
      <source>Add files…</source>
      <translation>添加文件…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="154" />
      <source>Open survey folder…</source>
      <translation>打开测量文件夹…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="156" />
      <source>Remove</source>
      <translation>移除</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="158" />
      <source>Check files</source>
      <translation>检查文件</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="165" />
      <source>Survey name</source>
      <translation>测量名称</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="166" />
      <source>GPS week</source>
      <translation>GPS 周</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="167" />
      <source>IMU profile</source>
      <translation>IMU 误差模型</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="273" />
      <source>Raw files of one survey</source>
      <translation>一次测量的原始文件</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="310" />
      <source>ok</source>
      <translation>正常</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="443" />
      <source>Import raw files as a survey</source>
      <translation>导入原始数据为测量</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="449" />
      <source>Import</source>
      <translation>导入</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="118" />
      <source>File</source>
      <translation>文件</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="118" />
      <source>Role</source>
      <translation>用途</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="118" />
      <source>Format</source>
      <translation>格式</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="118" />
      <source>Check</source>
      <translation>检测项</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="127" />
      <source>Line</source>
      <translation>行</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="127" />
      <source>What is wrong</source>
      <translation>问题</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="172" />
      <source>First rows of the selected file</source>
      <translation>所选文件的前几行</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="177" />
      <source>Problems found by the readers</source>
      <translation>读取时发现的问题</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="313" />
      <source>no role</source>
      <translation>未指定用途</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="90" />
      <source>cannot read: {error}</source>
      <translation>无法读取：{error}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="278" />
      <source>Survey folder (with {file})</source>
      <translation>测量文件夹（含 {file}）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="306" />
      <source>no file gives the position: give a GNSS solution (gnss) or total-station prism fixes (prism)</source>
      <translation>没有提供位置的文件：请给出 GNSS 解（gnss）或全站仪棱镜定位（prism）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="316" />
      <source>duplicate role</source>
      <translation>用途重复</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="394" />
      <source>no trolley geometry: enter it in the project</source>
      <translation>无小车几何参数：请在项目中填写</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="397" />
      <source>enter a survey name</source>
      <translation>请输入测量名称</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="82" />
      <source>not a readable .npy file: {error}</source>
      <translation>不是可读取的 .npy 文件：{error}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="85" />
      <source>{count} records</source>
      <translation>{count} 条记录</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="312" />
      <source>choose the role of this file</source>
      <translation>请选择此文件的用途</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="319" />
      <source>no format</source>
      <translation>未识别格式</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="323" />
      <source>format does not fit the role</source>
      <translation>格式与用途不符</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="303" />
      <source>no file has the role {role} (required: {required})</source>
      <translation>没有用途为 {role} 的文件（必需：{required}）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="318" />
      <source>format not recognised: choose one</source>
      <translation>未识别格式：请选择</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="315" />
      <source>more than one file has the role {role}</source>
      <translation>多个文件的用途为 {role}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="412" />
      <source>cannot copy into {folder}: {error}</source>
      <translation>无法复制到 {folder}：{error}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="321" />
      <source>format {format} does not hold {role} data</source>
      <translation>格式 {format} 不含 {role} 数据</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/importer.py" line="331" />
      <source>{unit} {line}: {message}</source>
      <translation>第 {line} {unit}：{message}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/loader.py" line="55" />
      <source>internal error {kind}: {error} (details on the console; please report it)</source>
      <translation>内部错误 {kind}：{error}（详情见控制台；请报告此问题）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/logpanel.py" line="29" />
      <source>warning: </source>
      <translation>警告：</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/logpanel.py" line="32" />
      <source>error: </source>
      <translation>错误：</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="95" />
      <source>Ready</source>
      <translation>就绪</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="149" />
      <source>Properties</source>
      <translation>属性</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="150" />
      <source>Log</source>
      <translation>日志</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="157" />
      <source>Cancel</source>
      <translation>取消</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="160" />
      <source>Open folder</source>
      <translation>打开文件夹</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="161" />
      <source>Open the folder of the exported report</source>
      <translation>打开导出报告所在的文件夹</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="216" />
      <source>&amp;New project…</source>
      <translation>新建项目(&amp;N)…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="217" />
      <source>Create a project with the wizard</source>
      <translation>用向导创建项目</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="218" />
      <source>&amp;Open project…</source>
      <translation>打开项目(&amp;O)…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="219" />
      <source>&amp;Save project</source>
      <translation>保存项目(&amp;S)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="220" />
      <source>&amp;Import raw files…</source>
      <translation>导入原始数据(&amp;I)…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="221" />
      <source>Add a survey from raw files</source>
      <translation>从原始数据添加测量</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="222" />
      <source>&amp;Process</source>
      <translation>处理(&amp;P)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="222" />
      <source>Process every survey of the project</source>
      <translation>处理项目的全部测量</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="223" />
      <source>Post-process &amp;GNSS</source>
      <translation>GNSS 后处理(&amp;G)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="224" />
      <source>Run the PPK stage (RTKLIB) of the survey on the GNSS page</source>
      <translation>对 GNSS 页的测量运行 PPK 后处理（RTKLIB）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="225" />
      <source>Re-design for &amp;tamping</source>
      <translation>捣固整道设计(&amp;T)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="226" />
      <source>Compute the lift and slew per sleeper of the survey shown after which the track passes the tolerance profile (a tamping machine's job)</source>
      <translation>计算所显示测量每根轨枕的起道量和拨道量，使作业后的线路满足容许偏差标准（捣固车作业）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="228" />
      <source>&amp;Cancel</source>
      <translation>取消(&amp;C)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="229" />
      <source>Stop the running job (processing, export, GNSS)</source>
      <translation>停止正在运行的任务（处理、导出、GNSS）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="230" />
      <source>&amp;Excel workbook…</source>
      <translation>Excel 工作簿(&amp;E)…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="231" />
      <source>Export the crews' Excel workbook of the survey shown</source>
      <translation>导出当前测量的作业班组 Excel 工作簿</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="232" />
      <source>Export Excel</source>
      <translation>导出 Excel</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="233" />
      <source>&amp;PDF report…</source>
      <translation>PDF 报告(&amp;P)…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="234" />
      <source>Export the PDF survey report of the survey shown</source>
      <translation>导出当前测量的 PDF 测量报告</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="235" />
      <source>Export PDF</source>
      <translation>导出 PDF</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="237" />
      <source>&amp;Plan survey…</source>
      <translation>测量规划(&amp;P)…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="238" />
      <source>Predict the accuracy of a planned survey (IMU, GNSS, speed, aiding)</source>
      <translation>预测计划测量的精度（IMU、GNSS、速度、辅助观测）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="239" />
      <source>&amp;Quit</source>
      <translation>退出(&amp;Q)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="241" />
      <source>&amp;File</source>
      <translation>文件(&amp;F)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="244" />
      <source>Open &amp;recent</source>
      <translation>最近打开(&amp;R)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="248" />
      <source>&amp;Export</source>
      <translation>导出(&amp;E)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="256" />
      <source>&amp;Run</source>
      <translation>运行(&amp;R)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="261" />
      <source>&amp;Tools</source>
      <translation>工具(&amp;T)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="263" />
      <source>&amp;View</source>
      <translation>视图(&amp;V)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="266" />
      <source>&amp;Help</source>
      <translation>帮助(&amp;H)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="267" />
      <source>&amp;About insrail</source>
      <translation>关于 insrail(&amp;A)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="269" />
      <source>Main</source>
      <translation>主工具栏</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="283" />
      <source>Project &amp;settings…</source>
      <translation>项目设置(&amp;S)…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="284" />
      <source>Edit the project's settings (coordinate system, trolley, processing, assessment)</source>
      <translation>编辑项目设置（坐标系、小车、数据处理、评估）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="286" />
      <source>&amp;Undo</source>
      <translation>撤销(&amp;U)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="288" />
      <source>&amp;Redo</source>
      <translation>重做(&amp;R)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="290" />
      <source>&amp;Edit</source>
      <translation>编辑(&amp;E)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="295" />
      <source>&amp;Preferences…</source>
      <translation>首选项(&amp;P)…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="296" />
      <source>The application's language</source>
      <translation>应用程序的语言</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="358" />
      <source>Unsaved changes</source>
      <translation>未保存的修改</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="465" />
      <source>Processing failed</source>
      <translation>处理失败</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="468" />
      <source>processing cancelled; previous results kept</source>
      <translation>处理已取消；保留之前的结果</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="706" />
      <source>export cancelled; nothing written</source>
      <translation>导出已取消；未写入任何文件</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="761" />
      <source>GNSS post-processing failed</source>
      <translation>GNSS 后处理失败</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="765" />
      <source> (from the cache)</source>
      <translation>（取自缓存）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="765" />
      <source> (computed now)</source>
      <translation>（本次计算）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="773" />
      <source>GNSS post-processing cancelled</source>
      <translation>GNSS 后处理已取消</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="793" />
      <source>Tamping re-design failed</source>
      <translation>捣固整道设计失败</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="832" />
      <source>About insrail</source>
      <translation>关于 insrail</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="117" />
      <source>Track</source>
      <translation>轨道</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="117" />
      <source>Plan</source>
      <translation>平面</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="117" />
      <source>Navigation</source>
      <translation>导航</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="118" />
      <source>Repeatability</source>
      <translation>重复性</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="118" />
      <source>Re-design</source>
      <translation>整道设计</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="119" />
      <source>GNSS</source>
      <translation>GNSS</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="347" />
      <source>no project — insrail</source>
      <translation>无项目 — insrail</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="377" />
      <source>Open project</source>
      <translation>打开项目</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="492" />
      <source>Cancelling…</source>
      <translation>正在取消…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="702" />
      <source>Written {name} in {folder}</source>
      <translation>已写入 {name}，位于 {folder}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="832" />
      <source>Inertial track-geometry trolley processing: GNSS/INS/odometer fusion, track geometry, reports.</source>
      <translation>惯性轨道几何测量小车数据处理：GNSS/INS/里程计组合导航、轨道几何、报告。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="322" />
      <source>settings saved to {path}; {rerun}</source>
      <translation>设置已保存至 {path}；{rerun}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="358" />
      <source>Save the changes to {project}?</source>
      <translation>保存对 {project} 的修改？</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="377" />
      <source>insrail project (project.toml)</source>
      <translation>insrail 项目 (project.toml)</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="383" />
      <source>Cannot open the project</source>
      <translation>无法打开项目</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="399" />
      <source>project {name}: {path}</source>
      <translation>项目 {name}：{path}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="418" />
      <source>Cannot save the project</source>
      <translation>无法保存项目</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="422" />
      <source>saved {path}</source>
      <translation>已保存 {path}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="448" />
      <source>Cannot add the survey</source>
      <translation>无法添加测量</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="451" />
      <source>survey {name} imported from {folder}</source>
      <translation>测量 {name} 已从 {folder} 导入</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="465" />
      <source>processing {surveys}</source>
      <translation>正在处理 {surveys}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="513" />
      <source>{survey}: {count} exceedances, results in {folder}</source>
      <translation>{survey}：超限 {count} 处，结果位于 {folder}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="600" />
      <source>Showing survey {survey}</source>
      <translation>正在显示测量 {survey}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="694" />
      <source>{kind} {start:.3f}–{end:.3f} m marked in {file}; processing again assesses with it</source>
      <translation>已在 {file} 中标记{kind} {start:.3f}–{end:.3f} m；重新处理后按其评定</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="701" />
      <source>written {path}</source>
      <translation>已写入 {path}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="757" />
      <source>survey {survey}: GNSS</source>
      <translation>测量 {survey}：GNSS</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="761" />
      <source>post-processing the GNSS of {survey}</source>
      <translation>正在对测量 {survey} 的 GNSS 进行后处理</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="767" />
      <source>GNSS of {survey}: fix rate {rate:.1f} % of {epochs} epochs{source}</source>
      <translation>测量 {survey} 的 GNSS：{epochs} 个历元中固定率 {rate:.1f} %{source}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="790" />
      <source>survey {survey}: tamping re-design</source>
      <translation>测量 {survey}：捣固重新设计</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="792" />
      <source>tamping re-design cancelled; nothing written</source>
      <translation>捣固重新设计已取消；未写入任何文件</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="793" />
      <source>re-designing {survey} for tamping</source>
      <translation>正在为捣固重新设计测量 {survey}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="800" />
      <source>{survey} re-designed: largest lift {lift_mm:.1f} mm, largest slew {slew_mm:.1f} mm; exceedances of {profile}: {before} before, {after} after the job</source>
      <translation>{survey} 已重新设计：最大起道量 {lift_mm:.1f} mm，最大拨道量 {slew_mm:.1f} mm；{profile} 超限：作业前 {before} 处，作业后 {after} 处</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="511" />
      <source>{survey}: {file} is older than these results: the banner over the views writes it again</source>
      <translation>{survey}：{file} 早于当前结果：视图上方的提示栏可重新生成</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="805" />
      <source>{survey}: cannot pass under the constraints: {what} {from_m:.1f}-{to_m:.1f} m (peak {value_mm:.2f} mm)</source>
      <translation>{survey}：在约束下无法满足：{what} {from_m:.1f}-{to_m:.1f} m（峰值 {value_mm:.2f} mm）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="810" />
      <source>{survey}: {count} stretches pass after the job by less than the survey's uncertainty of the check (three stated 1-sigma): the true track there may not pass</source>
      <translation>{survey}：作业后 {count} 段检测值通过的余量小于测量不确定度（所述 1σ 的三倍）：实际线路在该处可能不通过</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="814" />
      <source>{survey}: not assessed after the job: {check} {direction} (stated 1-sigma {sigma_mm:.2f} mm against the limit {limit_mm:.1f} mm) over {where}</source>
      <translation>{survey}：作业后不评定：{check} {direction}（所述 1σ {sigma_mm:.2f} mm，限值 {limit_mm:.1f} mm），区段 {where}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="433" />
      <source>first survey's trolley geometry unavailable: {error}</source>
      <translation>无法读取第一个测量的小车几何参数：{error}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/main_window.py" line="640" />
      <source>the check channels are shown by their columns: {error}</source>
      <translation>检测通道按其列名显示：{error}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="63" />
      <source>5 m lag lateral</source>
      <translation>5 m 间隔横向</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="63" />
      <source>5 m lag vertical</source>
      <translation>5 m 间隔垂向</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="64" />
      <source>150 m lag lateral</source>
      <translation>150 m 间隔横向</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="64" />
      <source>150 m lag vertical</source>
      <translation>150 m 间隔垂向</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="65" />
      <source>cant</source>
      <translation>超高</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="111" />
      <source>Plan survey — predicted accuracy</source>
      <translation>测量规划 — 预测精度</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="120" />
      <source>IMU profile from resources/imu_profiles (bias, random walks)</source>
      <translation>resources/imu_profiles 中的 IMU 误差模型（零偏、随机游走）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="127" />
      <source>track length after a 300 s static alignment (about 1.5 s of computing per km)</source>
      <translation>300 s 静态对准后的线路长度（每公里约计算 1.5 s）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="129" />
      <source>none</source>
      <translation>无</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="130" />
      <source>a GNSS outage of this duration in the middle of the run</source>
      <translation>在测量中段的此时长 GNSS 中断</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="133" />
      <source>odometer</source>
      <translation>里程计</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="134" />
      <source>non-holonomic constraint (NHC)</source>
      <translation>非完整约束（NHC）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="135" />
      <source>zero-velocity updates at rest (ZUPT)</source>
      <translation>静止时零速修正（ZUPT）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="142" />
      <source>vary one parameter from the baseline, like the thesis's chapter 3</source>
      <translation>从基准变化一个参数（如论文第 3 章）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="148" />
      <source>GNSS σ horizontal</source>
      <translation>GNSS σ 水平</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="149" />
      <source>GNSS σ vertical</source>
      <translation>GNSS σ 高程</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="150" />
      <source>Speed</source>
      <translation>速度</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="151" />
      <source>Track length</source>
      <translation>线路长度</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="152" />
      <source>GNSS outage mid-run</source>
      <translation>中段 GNSS 中断</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="153" />
      <source>Solution</source>
      <translation>解算</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="154" />
      <source>Aiding</source>
      <translation>辅助观测</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="159" />
      <source>Sweep</source>
      <translation>参数扫描</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="160" />
      <source>Values</source>
      <translation>取值</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="162" />
      <source>Run</source>
      <translation>运行</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="187" />
      <source>Set the planned run and press Run.</source>
      <translation>设置计划测量后按“运行”。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="258" />
      <source>prediction</source>
      <translation>精度预测</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="265" />
      <source>predicting…</source>
      <translation>正在预测…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="284" />
      <source>cancelled</source>
      <translation>已取消</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="322" />
      <source>done</source>
      <translation>完成</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="124" />
      <source>white (epoch-to-epoch) GNSS sigma; the fusion adds its correlated part</source>
      <translation>GNSS 白噪声（历元间）标准差；融合另加其相关部分</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="132" />
      <source>smoothed (RTS)</source>
      <translation>平滑解（RTS）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="132" />
      <source>forward filter</source>
      <translation>前向滤波</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="315" />
      <source>smoothed solution</source>
      <translation>平滑解</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="315" />
      <source>forward solution</source>
      <translation>前向解</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="329" />
      <source>Figure</source>
      <translation>指标</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="329" />
      <source>Limit [mm]</source>
      <translation>限值 [mm]</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="329" />
      <source>3σ against the limit</source>
      <translation>3σ 与限值比较</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="350" />
      <source>Figure, 1σ [mm]</source>
      <translation>指标，1σ [mm]</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="224" />
      <source>values in {unit}, separated by spaces; empty: the typical range shown</source>
      <translation>以 {unit} 为单位的数值，以空格分隔；留空：采用所示的典型范围</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="316" />
      <source>{solution}, 1 sigma [mm], {parameter} in {unit}; the plot shows 3 sigma against the limits</source>
      <translation>{solution}，1 倍标准差 [mm]，{parameter} 单位 {unit}；图中为 3 倍标准差与限值比较</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/plan_survey.py" line="236" />
      <source>sweep values: expected numbers separated by spaces, found {text}</source>
      <translation>扫描取值：应为以空格分隔的数字，实为 {text}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/preferences.py" line="18" />
      <source>Preferences</source>
      <translation>首选项</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/preferences.py" line="21" />
      <source>As the system (locale)</source>
      <translation>跟随系统（区域设置）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/preferences.py" line="26" />
      <source>Language</source>
      <translation>语言</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/preferences.py" line="27" />
      <source>The language changes when insrail is started again. The reports keep their project's language (Project settings, Report).</source>
      <translation>重新启动 insrail 后语言生效。报告使用其项目的语言（项目设置 &gt; 报告）。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="66" />
      <source>(each survey's own)</source>
      <translation>（各测量自带）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="68" />
      <source>not given</source>
      <translation>未给定</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="70" />
      <source>forward</source>
      <translation>前</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="70" />
      <source>right</source>
      <translation>右</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="70" />
      <source>down</source>
      <translation>下</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="72" />
      <source>roll</source>
      <translation>横滚</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="72" />
      <source>pitch</source>
      <translation>俯仰</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="72" />
      <source>heading</source>
      <translation>航向</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="74" />
      <source>fusion</source>
      <translation>组合导航</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="74" />
      <source>track reconstruction</source>
      <translation>轨道重建</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="74" />
      <source>assessment</source>
      <translation>评估</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="74" />
      <source>adjustment</source>
      <translation>调整量计算</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="114" />
      <source>Coordinate system</source>
      <translation>坐标系</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="126" />
      <source>Heights</source>
      <translation>高程</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="129" />
      <source>Trolley</source>
      <translation>小车</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="133" />
      <source>Processing</source>
      <translation>数据处理</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="144" />
      <source>Report</source>
      <translation>报告</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="219" />
      <source>Each survey brings its own trolley geometry (its survey.toml).</source>
      <translation>每个测量使用自己的小车几何参数（其 survey.toml）。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="220" />
      <source>Use one trolley for the whole project (the first survey's)</source>
      <translation>整个项目使用同一小车（取第一个测量的）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="459" />
      <source>Trolley for the whole project</source>
      <translation>整个项目使用同一小车</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="233" />
      <source>Undo</source>
      <translation>撤销</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="233" />
      <source>Redo</source>
      <translation>重做</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="333" />
      <source>the trolley's body frame b: x forward, y right, z down (FRD)</source>
      <translation>小车载体坐标系 b：x 向前，y 向右，z 向下（前右下）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="199" />
      <source>Project settings — {project}</source>
      <translation>项目设置 — {project}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="456" />
      <source>The first survey's trolley geometry cannot be read: {error}</source>
      <translation>无法读取第一个测量的小车几何参数：{error}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="505" />
      <source>Changed: {settings}. Nothing is processed again; the reports show the change when written again.</source>
      <translation>已修改：{settings}。无需重新处理；重新生成报告时即体现此修改。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="519" />
      <source>Cannot write {path}: {error}</source>
      <translation>无法写入 {path}：{error}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="500" />
      <source>Changed: {settings}. Processing again will run: {stages}.</source>
      <translation>已修改：{settings}。重新处理将运行：{stages}。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/settings_editor.py" line="501" />
      <source>Changed: {settings}. Processing again will run: {stages} (the earlier stages from the cache).</source>
      <translation>已修改：{settings}。重新处理将运行：{stages}（之前的步骤取自缓存）。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/exceedances.py" line="18" />
      <source>Rail</source>
      <translation>钢轨</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/exceedances.py" line="18" />
      <source>Direction</source>
      <translation>方向</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/exceedances.py" line="18" />
      <source>From [m]</source>
      <translation>起点 [m]</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/exceedances.py" line="18" />
      <source>To [m]</source>
      <translation>终点 [m]</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/exceedances.py" line="19" />
      <source>Peak</source>
      <translation>峰值</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/exceedances.py" line="19" />
      <source>Limit</source>
      <translation>限值</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/exceedances.py" line="19" />
      <source>Unit</source>
      <translation>单位</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/exceedances.py" line="19" />
      <source>Sleepers</source>
      <translation>轨枕</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="39" />
      <source>fix</source>
      <translation>固定解</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="39" />
      <source>float</source>
      <translation>浮点解</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="39" />
      <source>sbas</source>
      <translation>SBAS</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="39" />
      <source>dgps</source>
      <translation>伪距差分（DGPS）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="40" />
      <source>single</source>
      <translation>单点定位</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="40" />
      <source>ppp</source>
      <translation>精密单点定位（PPP）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="51" />
      <source>excluded</source>
      <translation>不采用</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="77" />
      <source>base (RINEX)</source>
      <translation>基准站（RINEX）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="78" />
      <source>navigation</source>
      <translation>导航星历</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="79" />
      <source>precise</source>
      <translation>精密星历</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="98" />
      <source>Files</source>
      <translation>文件</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="98" />
      <source>Base</source>
      <translation>基准站</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="105" />
      <source>epochs</source>
      <translation>历元</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="107" />
      <source>fix rate</source>
      <translation>固定率</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="108" />
      <source>ratio of fixed epochs</source>
      <translation>固定解历元的比率检验值</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="125" />
      <source>point</source>
      <translation>点</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="131" />
      <source>derivation</source>
      <translation>来源</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="133" />
      <source>Epochs by quality</source>
      <translation>各解类型历元数</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="133" />
      <source>Sigma by quality</source>
      <translation>各解类型标准差</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="135" />
      <source>Warnings</source>
      <translation>警告</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="178" />
      <source>Not post-processed yet: Run &gt; Post-process GNSS.</source>
      <translation>尚未后处理：“运行 &gt; GNSS 后处理”。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="180" />
      <source>Input</source>
      <translation>输入</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="181" />
      <source>QC</source>
      <translation>质量检查</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="191" />
      <source>time from the first epoch [s]</source>
      <translation>自首历元起的时间 [s]</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="242" />
      <source>&lt;b&gt;Fix rate {fix_rate:.1f} %&lt;/b&gt; of {epochs} epochs, 1 gap</source>
      <translation>{epochs} 个历元中&lt;b&gt;固定率 {fix_rate:.1f} %&lt;/b&gt;，1 处中断</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="242" />
      <source>&lt;b&gt;Fix rate {fix_rate:.1f} %&lt;/b&gt; of {epochs} epochs, {gaps} gaps</source>
      <translation>{epochs} 个历元中&lt;b&gt;固定率 {fix_rate:.1f} %&lt;/b&gt;，{gaps} 处中断</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="53" />
      <source>sigma x {factor}</source>
      <translation>σ × {factor}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="73" />
      <source>rover (RINEX)</source>
      <translation>流动站（RINEX）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="75" />
      <source>rover log</source>
      <translation>流动站原始记录</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="83" />
      <source>RTKLIB config</source>
      <translation>RTKLIB 配置</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="83" />
      <source>trolley defaults (resources/gnss)</source>
      <translation>小车默认配置（resources/gnss）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="85" />
      <source>base point</source>
      <translation>基准点</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="85" />
      <source>RINEX header APPROX POSITION (metre level)</source>
      <translation>RINEX 文件头 APPROX POSITION（米级）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="96" />
      <source>antenna height (ARP)</source>
      <translation>天线高（ARP）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="97" />
      <source>antenna type</source>
      <translation>天线类型</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="111" />
      <source>RTKLIB time</source>
      <translation>RTKLIB 耗时</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="127" />
      <source>baseline</source>
      <translation>基线长</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="129" />
      <source>mark lat, lon, h</source>
      <translation>标志点纬度、经度、大地高</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="197" />
      <source>Survey</source>
      <translation>测量</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="270" />
      <source>Position σ [mm]</source>
      <translation>位置 σ [mm]</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="69" />
      <source>{file} (missing)</source>
      <translation>{file}（缺失）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="89" />
      <source>coordinates</source>
      <translation>坐标</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="89" />
      <source>not in the project's control points</source>
      <translation>不在项目的控制点中</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="105" />
      <source>{epochs} over {span_s:.0f} s (interval {interval_s:g} s)</source>
      <translation>{epochs} 个，历时 {span_s:.0f} s（间隔 {interval_s:g} s）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="108" />
      <source>min {min}, 5 % {p05}, median {median}</source>
      <translation>最小 {min}，5 % 分位 {p05}，中位数 {median}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="115" />
      <source>; fusion: {use}</source>
      <translation>；组合解算：{use}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="117" />
      <source>horizontal median {h_median:.1f} mm, 95 % {h_p95:.1f} mm; vertical median {v_median:.1f} mm, 95 % {v_p95:.1f} mm</source>
      <translation>水平中位数 {h_median:.1f} mm，95 % 分位 {h_p95:.1f} mm；垂直中位数 {v_median:.1f} mm，95 % 分位 {v_p95:.1f} mm</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="122" />
      <source>to +{end_s:.0f} s ({duration_s:.0f} s)</source>
      <translation>至 +{end_s:.0f} s（{duration_s:.0f} s）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="125" />
      <source> (approximate)</source>
      <translation>（近似）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="134" />
      <source>Gaps ({count})</source>
      <translation>中断（{count}）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="264" />
      <source>&lt;b&gt;Solution quality&lt;/b&gt;</source>
      <translation>&lt;b&gt;解的质量&lt;/b&gt;</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="270" />
      <source>horizontal</source>
      <translation>水平</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="270" />
      <source>vertical</source>
      <translation>垂直</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="92" />
      <source>lat, lon, h</source>
      <translation>纬度、经度、大地高</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/gnss.py" line="95" />
      <source>E, N, H (normal)</source>
      <translation>东、北坐标，正常高</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/navigation.py" line="80" />
      <source>, 1σ band</source>
      <translation>，1σ 带</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/navigation.py" line="97" />
      <source>GPS time of week [s]</source>
      <translation>GPS 周内秒 [s]</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/plan.py" line="113" />
      <source>trajectory (IMU)</source>
      <translation>轨迹（IMU）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/plan.py" line="122" />
      <source>GNSS outage</source>
      <translation>GNSS 中断</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/redesign.py" line="40" />
      <source>chainage [m]</source>
      <translation>里程 [m]</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/redesign.py" line="70" />
      <source>measured</source>
      <translation>实测</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/redesign.py" line="70" />
      <source>after tamping</source>
      <translation>捣固后</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/redesign.py" line="51" />
      <source>No re-design of this survey: Run &gt; Re-design for tamping computes the lift and slew after which the track passes the tolerance profile.</source>
      <translation>此测量尚无整道设计：“运行 &gt; 捣固整道设计”计算起道量和拨道量，使作业后的线路满足容许偏差标准。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/redesign.py" line="72" />
      <source>Vertical (mean of the rails) [mm]</source>
      <translation>高低（两轨平均）[mm]</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/redesign.py" line="74" />
      <source>Lateral (mean of the rails) [mm]</source>
      <translation>轨向（两轨平均）[mm]</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/redesign.py" line="76" />
      <source>Lift and slew [mm]</source>
      <translation>起道量和拨道量 [mm]</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/redesign.py" line="54" />
      <source>Survey {survey}, profile {profile}: largest lift {lift:.1f} mm, largest slew {slew:.1f} mm; exceedances {before} before, {after} after the job; {cannot} stretches cannot pass under the constraints, {uncertain} pass by less than the survey's uncertainty, {not_assessed} checks not assessed (the log lists them).</source>
      <translation>测量 {survey}，容许偏差标准 {profile}：最大起道量 {lift:.1f} mm，最大拨道量 {slew:.1f} mm；超限作业前 {before} 处，作业后 {after} 处；{cannot} 段在约束下无法达标，{uncertain} 段通过余量小于测量不确定度，{not_assessed} 项检测不评定（见日志）。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/redesign.py" line="76" />
      <source>lift left rail</source>
      <translation>左轨起道量</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/redesign.py" line="77" />
      <source>lift right rail</source>
      <translation>右轨起道量</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/redesign.py" line="77" />
      <source>slew</source>
      <translation>拨道量</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/repeatability.py" line="36" />
      <source>Parameter:</source>
      <translation>参数：</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/repeatability.py" line="67" />
      <source>: process more surveys of this track to compare them</source>
      <translation>：处理本线路的更多测量以进行比较</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/repeatability.py" line="66" />
      <source>{count} runs</source>
      <translation>{count} 个测次</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/repeatability.py" line="66" />
      <source>{count} run</source>
      <translation>{count} 个测次</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/track.py" line="60" />
      <source>Move the mouse over the plots to read every value at a sleeper.</source>
      <translation>将鼠标移到曲线上可读取该轨枕处的全部数值。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/track.py" line="396" />
      <source>Go to: #sleeper, K1+234.5 or station</source>
      <translation>转到：#轨枕号、K1+234.5 或里程</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/track.py" line="397" />
      <source>Go to a sleeper (#123), a chainage as printed on the sleepers (K1+234.5) or a station in metres; Enter</source>
      <translation>转到轨枕（#123）、轨枕上标注的里程（K1+234.5）或以米计的里程；回车</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/track.py" line="403" />
      <source>Measuring tool: click two points of a plot to read the chainage and value differences between them</source>
      <translation>量测工具：在曲线上点击两点，读取两点间的里程差和数值差</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/track.py" line="412" />
      <source>Mark the span between the two measured points as a turnout, level crossing, bridge, joint, stretch not to assess or note in the project's event file</source>
      <translation>在项目的事件文件中将两量测点之间标记为道岔、平交道口、桥梁、接头、不评估地段或备注</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/track.py" line="401" />
      <source>Measure</source>
      <translation>量测</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/track.py" line="411" />
      <source>Mark as track event…</source>
      <translation>标记为线路事件…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/track.py" line="417" />
      <source>Plots</source>
      <translation>曲线</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/track.py" line="684" />
      <source>Measuring: click the first point in a plot.</source>
      <translation>量测：在曲线上点击第一点。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/track.py" line="701" />
      <source>Measuring: click the second point.</source>
      <translation>量测：点击第二点。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/track.py" line="667" />
      <source>&lt;b&gt;{label}&lt;/b&gt; sleeper {number} ({station:.3f} m)</source>
      <translation>&lt;b&gt;{label}&lt;/b&gt; 轨枕 {number}（{station:.3f} m）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/track.py" line="652" />
      <source>{text} is no sleeper number, chainage or station of this survey</source>
      <translation>{text} 不是本测量的轨枕号、里程或测站</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/track.py" line="676" />
      <source>&lt;b&gt;not assessed&lt;/b&gt;: {why}</source>
      <translation>&lt;b&gt;不评定&lt;/b&gt;：{why}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/track.py" line="710" />
      <source>Δ chainage &lt;b&gt;{length:+.3f} m&lt;/b&gt; (sleeper {first} {first_label} → {second} {second_label})</source>
      <translation>Δ 里程 &lt;b&gt;{length:+.3f} m&lt;/b&gt;（轨枕 {first} {first_label} → {second} {second_label}）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/views/track.py" line="191" />
      <source>±{sigmas:g}σ predicted</source>
      <translation>预测 ±{sigmas:g}σ</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="69" />
      <source>Browse…</source>
      <translation>浏览…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="110" />
      <source>New insrail project</source>
      <translation>新建 insrail 项目</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="160" />
      <source>Where the project file (project.toml) and the results are kept.</source>
      <translation>项目文件（project.toml）和结果的存放位置。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="161" />
      <source>New project</source>
      <translation>新项目</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="170" />
      <source>Name</source>
      <translation>名称</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="171" />
      <source>Folder</source>
      <translation>文件夹</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="172" />
      <source>Description</source>
      <translation>说明</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="176" />
      <source>The engineering (construction) coordinate system: a transverse Mercator projection on the chosen ellipsoid, reduced to the projection height.</source>
      <translation>工程（施工）坐标系：所选椭球上的横轴墨卡托（高斯-克吕格）投影，归算到投影面高程。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="201" />
      <source>Benchmarks</source>
      <translation>水准点</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="201" />
      <source>GNSS-levelling benchmarks (ellipsoidal and normal heights) fit the height anomaly; without them heights stay ellipsoidal.</source>
      <translation>GNSS 水准点（大地高与正常高）用于拟合高程异常；没有水准点时高程为大地高。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="206" />
      <source>Benchmarks file</source>
      <translation>水准点文件</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="208" />
      <source>Height-anomaly model</source>
      <translation>高程异常模型</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="212" />
      <source>Trolley geometry</source>
      <translation>小车几何参数</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="212" />
      <source>Lever arms from the IMU centre in the IMU body frame (forward, right, down), metres; mounting angles of the IMU in the trolley.</source>
      <translation>IMU 中心至各传感器的杆臂，IMU 载体坐标系（前、右、下），单位 m；IMU 在小车上的安装角。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="233" />
      <source>Copy from a survey.toml…</source>
      <translation>从 survey.toml 复制…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="236" />
      <source>Copy the trolley of an earlier project…</source>
      <translation>复制以往项目的小车…</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="240" />
      <source>These lever arms really are zero</source>
      <translation>这些杆臂确实为零</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="243" />
      <source>Reference rail</source>
      <translation>基准轨</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="244" />
      <source>Rail centre spacing (cant base)</source>
      <translation>两轨中心距（超高基长）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="258" />
      <source>Processing and assessment</source>
      <translation>数据处理与评估</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="258" />
      <source>IMU error model, design alignment, tolerance profile for the assessment and the fastener type for the adjustment.</source>
      <translation>IMU 误差模型、设计线形、评估用的容许偏差标准及调整用的扣件类型。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="270" />
      <source>Design alignment</source>
      <translation>设计线形</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="272" />
      <source>Start station (without a design)</source>
      <translation>起点里程（无设计线形时）</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="273" />
      <source>Tolerance profile</source>
      <translation>容许偏差标准</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="274" />
      <source>Fastener type</source>
      <translation>扣件类型</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="278" />
      <source>First survey</source>
      <translation>第一个测量</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="278" />
      <source>The raw files of one trolley run; formats are detected, check them before finishing.</source>
      <translation>一次小车推行的原始数据；格式自动识别，完成前请检查。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="281" />
      <source>Keep the raw files where they are</source>
      <translation>原始数据保留在原位置</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="282" />
      <source>Copy the raw files into the project (surveys/&lt;survey name&gt;/); the raw-data folder is left as it is</source>
      <translation>将原始数据复制到项目中（surveys/&lt;测量名称&gt;/）；原始数据文件夹保持不变</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="457" />
      <source>choose the folder for the project file and its results</source>
      <translation>请选择存放项目文件及其结果的文件夹</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="189" />
      <source>Ellipsoid</source>
      <translation>椭球</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="189" />
      <source>Central meridian</source>
      <translation>中央子午线</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="191" />
      <source>Latitude of origin</source>
      <translation>原点纬度</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="192" />
      <source>Scale factor</source>
      <translation>比例因子</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="192" />
      <source>False easting</source>
      <translation>东偏移</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="194" />
      <source>False northing</source>
      <translation>北偏移</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="195" />
      <source>Projection height</source>
      <translation>投影面高程</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="196" />
      <source>Projection height applied as</source>
      <translation>投影面高程的处理方式</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="512" />
      <source>Choose the project folder (first page).</source>
      <translation>请选择项目文件夹（第一页）。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="515" />
      <source>Add the raw files of the first survey.</source>
      <translation>请添加第一个测量的原始数据。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="536" />
      <source>The survey's files have problems (listed above).</source>
      <translation>测量文件有问题（见上方列表）。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="483" />
      <source>0 m: is this lever arm measured?</source>
      <translation>0 m：此杆臂是否已实测？</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="459" />
      <source>{folder} is a file, not a folder</source>
      <translation>{folder} 是文件，不是文件夹</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="491" />
      <source>Lever arms at 0 m: {arms}. A trolley's sensors are never all at the IMU centre: enter the measured lever arms, copy them from an earlier project, or confirm below that they really are zero.</source>
      <translation>杆臂为 0 m：{arms}。小车的传感器不可能都位于 IMU 中心：请输入实测杆臂、从以往项目复制，或在下方确认其确实为零。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="533" />
      <source>{folder} is not empty: choose another survey name.</source>
      <translation>{folder} 不为空：请另选测量名称。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="308" />
      <source>The files and survey.toml go into {folder}.</source>
      <translation>文件及 survey.toml 将放入 {folder}。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="310" />
      <source>survey.toml (the description of the survey's files) will be written into the raw-data folder {folder}.</source>
      <translation>survey.toml（测量文件的说明）将写入原始数据文件夹 {folder}。</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="461" />
      <source>a project already exists in {folder}: open it, or choose another folder</source>
      <translation>{folder} 中已有项目：请打开它，或选择其他文件夹</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="466" />
      <source>cannot create the folder: {error}</source>
      <translation>无法创建文件夹：{error}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="470" />
      <source>created the folder {folder}</source>
      <translation>已创建文件夹 {folder}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="339" />
      <source>the trolley of {path} cannot be read: {error}</source>
      <translation>无法读取 {path} 的小车参数：{error}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/wizard.py" line="530" />
      <source>The project has problems; go back and correct them:</source>
      <translation>项目存在问题；请返回更正：</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/worker.py" line="78" />
      <source>survey {survey}</source>
      <translation>测量 {survey}</translation>
    </message>
    <message>
      <location filename="../../../insrail/gui/worker.py" line="57" />
      <source>{subject}: internal error {kind}: {error} (details on the console; please report it)</source>
      <translation>{subject}：内部错误 {kind}：{error}（详情见控制台；请报告此问题）</translation>
    </message>
  </context>
</TS>
